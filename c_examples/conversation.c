/* conversation.c: two characters stand facing each other 1.2 m apart and talk in turns; a
 * third stands a little way off, in no conversation. The first two form a group
 * (cg_crowd_set_conversation); who talks comes with each frame (CG_STATE_TALKING), the turn
 * passing every 5 s. Over 20 s at 30 frames per second, prints the share of frames in which
 * the listener's eyes are on the speaker (people listening look at the speaker about three
 * quarters of the time, glancing away now and then), and fails unless it lies between 0.5
 * and 0.95. Then one of the two walks off: the group ends. */
#include <stdio.h>
#include <stdlib.h>

#include "crowdgaze.h"

#define FPS 30
#define SECONDS 20
#define TURN_SECONDS 5
#define PI_F 3.14159265f

static int failures = 0;
#define CHECK(cond)                                                                       \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);    \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

static void ok(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s: %s\n", what, message);
        exit(1);
    }
}

/* Adds a character standing at (x, 0, z) facing `heading`; returns its id. */
static uint32_t add_character(cg_crowd *crowd, float x, float z, float heading) {
    cg_character_desc desc;
    uint32_t id = CG_NO_TARGET;
    desc.struct_size = sizeof desc;
    ok(cg_character_desc_init(&desc), "cg_character_desc_init");
    desc.position.x = x;
    desc.position.z = z;
    desc.heading = heading;
    ok(cg_crowd_add_character(crowd, &desc, &id), "cg_crowd_add_character");
    return id;
}

int main(void) {
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    cg_entity_state states[3];
    cg_gaze_info gaze[3];
    uint32_t ids[3], group = CG_NO_TARGET, found = CG_NO_TARGET;
    /* Where each character stands and faces: the first two face each other (Y up, +Z
     * forward, heading counter-clockwise about Y), the third looks across at them. */
    const float x[3] = {0.0f, 0.0f, 3.0f}, z[3] = {0.0f, 1.2f, 0.6f};
    const float heading[3] = {0.0f, PI_F, -PI_F / 2.0f};
    int frame, i, listening = 0, listener_on_speaker = 0;
    float share;

    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "cg_crowd_config_init");
    config.seed = 6;
    config.max_characters = 3;
    config.max_objects = 0;
    ok(cg_crowd_create(&config, &crowd), "cg_crowd_create");
    for (i = 0; i < 3; i++) {
        ids[i] = add_character(crowd, x[i], z[i], heading[i]);
        states[i].struct_size = sizeof states[i];
        ok(cg_entity_state_init(&states[i]), "cg_entity_state_init");
        states[i].id = ids[i];
        states[i].position.x = x[i];
        states[i].position.z = z[i];
        states[i].heading = heading[i];
    }
    ok(cg_crowd_set_conversation(crowd, ids, 2, &group), "cg_crowd_set_conversation");
    ok(cg_crowd_get_conversation(crowd, ids[1], &found), "cg_crowd_get_conversation");
    CHECK(found == group);
    ok(cg_crowd_get_conversation(crowd, ids[2], &found), "cg_crowd_get_conversation");
    CHECK(found == CG_NO_TARGET);

    for (frame = 0; frame < SECONDS * FPS; frame++) {
        /* The first talks for 5 s, then the second, and so on. */
        const int speaker = (frame / (TURN_SECONDS * FPS)) % 2;
        const int listener = 1 - speaker;
        size_t written = 0;
        states[speaker].flags = CG_STATE_TALKING;
        states[listener].flags = 0;
        ok(cg_crowd_push_frame(crowd, (double)frame / FPS, states, 3), "cg_crowd_push_frame");
        ok(cg_crowd_step(crowd, 1.0f / FPS), "cg_crowd_step");
        ok(cg_crowd_read_gaze(crowd, gaze, 3, &written), "cg_crowd_read_gaze");
        CHECK(written == 3 && gaze[listener].character == ids[listener]);
        listening++;
        listener_on_speaker += gaze[listener].target == ids[speaker];
    }
    share = (float)listener_on_speaker / (float)listening;
    printf("listener's eyes on the speaker in %d of %d frames: share %.2f\n",
           listener_on_speaker, listening, (double)share);
    if (!(share >= 0.5f && share <= 0.95f)) {
        fprintf(stderr, "the share %.2f is not between 0.5 and 0.95\n", (double)share);
        cg_crowd_destroy(crowd);
        return 1;
    }

    /* The second walks off (is removed): a group left with one member ends. */
    ok(cg_crowd_remove_entity(crowd, ids[1]), "cg_crowd_remove_entity");
    ok(cg_crowd_get_conversation(crowd, ids[0], &found), "cg_crowd_get_conversation");
    CHECK(found == CG_NO_TARGET);
    CHECK(cg_crowd_remove_conversation(crowd, group) == CG_STATUS_NOT_FOUND);
    printf("group %u ended when one of its two members left\n", (unsigned)group);

    cg_crowd_destroy(crowd);
    if (failures != 0) {
        return 1;
    }
    printf("ok\n");
    return 0;
}
