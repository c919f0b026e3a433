/* street.c: the second example of Grillon & Thalmann 2009 — 130 characters walking up and
 * down a street, standing, or sitting on benches, with 60 scene objects and d_m = 10 m —
 * generated deterministically and run for 60 s at 30 fps. Prints each character's
 * attentive fraction (against its attention percentage a) and interest-point count, and the
 * mean cost per character-frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "crowdgaze.h"

#define CHARACTERS 130
#define OBJECTS 60
#define FPS 30
#define SECONDS 60
#define STREET_LENGTH 120.0f
#define STREET_WIDTH 14.0f

/* A small deterministic generator (xorshift32), so the scene is the same everywhere. */
static uint32_t rng_state = 2009u;
static float uniform(float low, float high) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return low + (high - low) * (float)(rng_state >> 8) / 16777216.0f;
}

typedef struct {
    float x, z, vx, vz; /* ground position and velocity, metres: x along the street */
    int walking;
} person;

static int check(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s failed: %s (%s)\n", what, cg_status_str(status), message);
        exit(1);
    }
    return 0;
}

int main(void) {
    static person people[CHARACTERS];
    static cg_entity_state states[CHARACTERS];
    static cg_gaze_info gaze[CHARACTERS];
    static float attention_fraction[CHARACTERS];
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    int i, frame, standing = 0, sitting = 0;
    size_t written = 0;
    double seconds_in_step = 0.0, mean_error = 0.0;
    float min_fraction = 1.0f, max_fraction = 0.0f;
    uint32_t total_interests = 0;

    check(cg_crowd_config_init(&config), "cg_crowd_config_init");
    config.seed = 130;
    config.max_characters = CHARACTERS;
    config.max_objects = OBJECTS;
    config.max_distance = 10.0f; /* d_m */
    /* Y up, heading 0 along +Z: the street runs along Z, its width along X. */
    check(cg_crowd_create(&config, &crowd), "cg_crowd_create");

    for (i = 0; i < OBJECTS; i++) {
        cg_object_desc object;
        uint32_t id;
        int left = i % 2 == 0;
        check(cg_object_desc_init(&object), "cg_object_desc_init");
        object.position.z = (float)(i / 2) * STREET_LENGTH / (OBJECTS / 2 + 1) + uniform(0.0f, 2.0f);
        object.position.x = left ? 0.3f : STREET_WIDTH - 0.3f;
        object.heading = left ? 1.5708f : -1.5708f; /* facing the street */
        object.look_at_height = (i % 4 == 2) ? 3.5f : 1.5f; /* lamps, windows */
        object.impact = uniform(0.3f, 1.0f);
        check(cg_crowd_add_object(crowd, &object, &id), "cg_crowd_add_object");
    }
    for (i = 0; i < CHARACTERS; i++) {
        cg_character_desc desc;
        cg_character_params params;
        float roll = uniform(0.0f, 1.0f);
        person *p = &people[i];
        p->z = uniform(0.0f, STREET_LENGTH);
        p->x = uniform(1.5f, STREET_WIDTH - 1.5f);
        p->vx = 0.0f;
        p->vz = 0.0f;
        p->walking = roll < 0.75f;
        check(cg_character_desc_init(&desc), "cg_character_desc_init");
        check(cg_entity_state_init(&states[i]), "cg_entity_state_init");
        if (p->walking) {
            p->vz = (uniform(0.0f, 1.0f) < 0.5f ? -1.0f : 1.0f) * uniform(0.9f, 1.6f);
            p->vx = uniform(-0.1f, 0.1f);
            states[i].flags = CG_STATE_HEADING_FROM_MOTION;
        } else if (roll < 0.9f) {
            standing++;
            desc.heading = uniform(-3.14159f, 3.14159f);
        } else {
            sitting++;
            p->x = roll < 0.95f ? 1.0f : STREET_WIDTH - 1.0f;
            desc.heading = p->x < 2.0f ? 1.5708f : -1.5708f;
        }
        desc.position.x = p->x;
        desc.position.z = p->z;
        check(cg_crowd_add_character(crowd, &desc, &states[i].id), "cg_crowd_add_character");
        states[i].heading = desc.heading;
        check(cg_crowd_get_character_params(crowd, states[i].id, &params), "get params");
        attention_fraction[i] = params.attention_fraction;
    }

    for (frame = 1; frame <= FPS * SECONDS; frame++) {
        const float dt = 1.0f / FPS;
        clock_t start;
        for (i = 0; i < CHARACTERS; i++) {
            person *p = &people[i];
            if (p->walking) {
                p->x += p->vx * dt;
                p->z += p->vz * dt;
                if (p->z < 0.0f || p->z > STREET_LENGTH) p->vz = -p->vz; /* turn back */
                if (p->x < 1.0f || p->x > STREET_WIDTH - 1.0f) p->vx = -p->vx;
            }
            states[i].position.x = p->x;
            states[i].position.z = p->z;
        }
        check(cg_crowd_push_frame(crowd, frame * (double)dt, states, CHARACTERS), "push_frame");
        start = clock();
        check(cg_crowd_step(crowd, dt), "cg_crowd_step");
        seconds_in_step += (double)(clock() - start) / CLOCKS_PER_SEC;
    }

    check(cg_crowd_read_gaze(crowd, gaze, CHARACTERS, &written), "cg_crowd_read_gaze");
    if (written != CHARACTERS) {
        fprintf(stderr, "read %zu gaze records\n", written);
        return 1;
    }
    printf("street: %d characters (%d standing, %d sitting), %d objects, %d s at %d fps\n",
           CHARACTERS, standing, sitting, OBJECTS, SECONDS, FPS);
    printf("character   a     attentive  interest points\n");
    for (i = 0; i < CHARACTERS; i++) {
        float fraction = gaze[i].attentive_fraction;
        if (gaze[i].character != states[i].id) {
            fprintf(stderr, "character order changed\n");
            return 1;
        }
        if (i < 10) {
            printf("%9u  %.2f   %.2f      %u\n", (unsigned)gaze[i].character,
                   attention_fraction[i], fraction, (unsigned)gaze[i].interest_count);
        }
        mean_error += fabs(fraction - attention_fraction[i]);
        total_interests += gaze[i].interest_count;
        if (fraction < min_fraction) min_fraction = fraction;
        if (fraction > max_fraction) max_fraction = fraction;
    }
    mean_error /= CHARACTERS;
    printf("... (%d more)\n", CHARACTERS - 10);
    printf("attentive fraction: min %.2f, max %.2f; mean |attentive - a| = %.3f\n", min_fraction,
           max_fraction, mean_error);
    printf("interest points: %u in all, %.1f per character per minute\n", (unsigned)total_interests,
           total_interests / (double)CHARACTERS / (SECONDS / 60.0));
    printf("attention step: %.2f us per character-frame (this build)\n",
           1e6 * seconds_in_step / ((double)CHARACTERS * FPS * SECONDS));
    cg_crowd_destroy(crowd);
    if (mean_error > 0.15 || total_interests < CHARACTERS) {
        fprintf(stderr, "implausible attention statistics\n");
        return 1;
    }
    printf("ok\n");
    return 0;
}
