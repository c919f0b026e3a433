/* street_following.c: the street preset and gaze following from C. Five people stand on the
 * pavement staring up at a window (game logic gives each an overriding gaze target at the
 * point), and 30 passers-by walk up and down past them with the street model
 * (CG_ATTENTION_MODEL_STREET, cg_crowd_config_init_street). Checks that many passers-by
 * glance at the window (cg_crowd_read_following), always at the point stared at, that the
 * starers themselves follow no one, and that following is off by default: a crowd with
 * follow_enabled = 0 gives bit-identical outputs to one whose config stops before the
 * street and following fields (an older, 216-byte layout, which gets their defaults). */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "crowdgaze.h"

#define STARERS 5
#define WALKERS 30
#define PEOPLE (STARERS + WALKERS)
#define FPS 30
#define SECONDS 40
#define STREET_END 25.0f /* walkers turn back at z = +-25 m */
#define JOINTS_PER_CHARACTER 10

/* A config whose struct_size stops before the street and following fields, as a program
 * built against the previous header has it (C pads the struct to 8 bytes). */
#define CONFIG_SIZE_BEFORE_STREET ((offsetof(cg_crowd_config, street_view_half_angle) + 7) / 8 * 8)

static const cg_vec3 WINDOW = {0.0f, 12.0f, -6.0f}; /* a window up across the street */

static void check(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256] = "";
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s: %s (%s)\n", what, cg_status_str(status), message);
        exit(1);
    }
}

static void require(int condition, const char *what) {
    if (!condition) {
        fprintf(stderr, "check failed: %s\n", what);
        exit(1);
    }
}

/* The street: its crowd, the people's ids, states and walking speeds. */
typedef struct {
    cg_crowd *crowd;
    uint32_t ids[PEOPLE];
    cg_entity_state states[PEOPLE];
    float speed[PEOPLE];
} street;

/* Creates the crowd from `config` and adds the starers (with their target) and walkers. */
static void populate(street *s, const cg_crowd_config *config) {
    int i;
    check(cg_crowd_create(config, &s->crowd), "cg_crowd_create");
    for (i = 0; i < PEOPLE; i++) {
        cg_character_desc desc;
        cg_entity_state *state = &s->states[i];
        desc.struct_size = sizeof desc;
        check(cg_character_desc_init(&desc), "cg_character_desc_init");
        desc.attention_model = CG_ATTENTION_MODEL_STREET;
        state->struct_size = sizeof *state;
        check(cg_entity_state_init(state), "cg_entity_state_init");
        if (i < STARERS) { /* in a row on the pavement at x = -1 .. 1, facing the street */
            desc.position.x = -1.0f + 0.5f * (float)i;
            desc.heading = 3.14159f;
            s->speed[i] = 0.0f;
        } else { /* lanes 2 to 6 m from the starers, half walking each way */
            int k = i - STARERS;
            desc.position.x = 2.0f + (float)(k % 5);
            desc.position.z = -STREET_END + (float)(k * 37 % 50);
            s->speed[i] = (k % 2 ? 1.0f : -1.0f) * (1.1f + 0.05f * (float)(k % 7));
            state->flags = CG_STATE_HEADING_FROM_MOTION;
        }
        check(cg_crowd_add_character(s->crowd, &desc, &s->ids[i]), "cg_crowd_add_character");
        state->id = s->ids[i];
        state->heading = desc.heading;
        state->position = desc.position;
    }
    for (i = 0; i < STARERS; i++) { /* game logic: stare at the window until cleared */
        cg_gaze_target target;
        target.struct_size = sizeof target;
        check(cg_gaze_target_init(&target), "cg_gaze_target_init");
        target.kind = CG_GAZE_TARGET_POINT;
        target.priority = CG_GAZE_PRIORITY_OVERRIDE;
        target.point = WINDOW;
        check(cg_crowd_set_gaze_target(s->crowd, s->ids[i], &target), "set_gaze_target");
    }
}

/* Walks the walkers on by one frame, pushes it and steps. */
static void advance(street *s, int frame) {
    const float dt = 1.0f / FPS;
    int i;
    for (i = STARERS; i < PEOPLE; i++) {
        cg_vec3 *p = &s->states[i].position;
        p->z += s->speed[i] * dt;
        if (fabsf(p->z) > STREET_END) s->speed[i] = -s->speed[i];
    }
    check(cg_crowd_push_frame(s->crowd, frame * (double)dt, s->states, PEOPLE), "push_frame");
    check(cg_crowd_step(s->crowd, dt), "cg_crowd_step");
}

/* Everything the crowd says of its characters' gaze after a step, as bytes. */
typedef struct {
    cg_gaze_info gaze[PEOPLE];
    cg_quat joints[PEOPLE * JOINTS_PER_CHARACTER];
} outputs;

static void read_outputs(const street *s, outputs *out) {
    size_t written = 0;
    memset(out, 0, sizeof *out);
    check(cg_crowd_read_gaze(s->crowd, out->gaze, PEOPLE, &written), "read_gaze");
    require(written == PEOPLE, "every character read");
    check(cg_crowd_read_joints(s->crowd, 0, PEOPLE, out->joints, PEOPLE * JOINTS_PER_CHARACTER),
          "read_joints");
}

/* The street preset: passers-by glance where the starers look. */
static void followers(void) {
    static street s;
    cg_crowd_config config;
    int frame, i, followers = 0, following_frames = 0;
    uint32_t glances_total = 0;
    config.struct_size = sizeof config;
    check(cg_crowd_config_init_street(&config), "cg_crowd_config_init_street");
    require(config.follow_enabled == 1 && config.max_distance == 17.0f, "the street preset");
    config.max_characters = PEOPLE;
    config.seed = 1969;
    populate(&s, &config);
    for (frame = 1; frame <= FPS * SECONDS; frame++) {
        advance(&s, frame);
        for (i = 0; i < PEOPLE; i++) {
            cg_vec3 point;
            uint32_t following = 0, glances = 0;
            check(cg_crowd_read_following(s.crowd, s.ids[i], &point, &following, &glances),
                  "cg_crowd_read_following");
            if (i < STARERS) {
                require(following == 0 && glances == 0, "a starer follows no one");
            } else if (following) {
                following_frames++;
                require(fabsf(point.x - WINDOW.x) < 1e-4f && fabsf(point.y - WINDOW.y) < 1e-4f &&
                            fabsf(point.z - WINDOW.z) < 1e-4f,
                        "a follower glances at the point stared at");
            }
        }
    }
    for (i = STARERS; i < PEOPLE; i++) {
        cg_vec3 point;
        uint32_t following = 0, glances = 0;
        check(cg_crowd_read_following(s.crowd, s.ids[i], &point, &following, &glances),
              "cg_crowd_read_following");
        followers += glances > 0;
        glances_total += glances;
    }
    printf("%d of %d passers-by glanced at the window (%u glances, %.1f s in all)\n", followers,
           WALKERS, (unsigned)glances_total, (double)following_frames / FPS);
    require(followers >= WALKERS / 3, "at least a third of the passers-by follow");
    cg_crowd_destroy(s.crowd);
}

/* follow_enabled = 0 is the crowd of a caller that never heard of the new fields. */
static void off_by_default(void) {
    static street off, old;
    static outputs a, b;
    cg_crowd_config config, *older;
    int frame, i;
    config.struct_size = sizeof config;
    check(cg_crowd_config_init_street(&config), "cg_crowd_config_init_street");
    config.follow_enabled = 0;
    config.max_characters = PEOPLE;
    config.seed = 1969;
    populate(&off, &config);

    older = malloc(CONFIG_SIZE_BEFORE_STREET); /* exactly the older layout's bytes */
    require(older != NULL, "memory");
    older->struct_size = CONFIG_SIZE_BEFORE_STREET;
    check(cg_crowd_config_init(older), "cg_crowd_config_init (216 bytes)");
    older->max_distance = 17.0f;
    older->max_characters = PEOPLE;
    older->seed = 1969;
    populate(&old, older);
    free(older);

    for (frame = 1; frame <= FPS * SECONDS; frame++) {
        advance(&off, frame);
        advance(&old, frame);
        read_outputs(&off, &a);
        read_outputs(&old, &b);
        require(memcmp(&a, &b, sizeof a) == 0, "bit-identical outputs");
    }
    for (i = 0; i < PEOPLE; i++) {
        cg_vec3 point;
        uint32_t following = 1, glances = 1;
        check(cg_crowd_read_following(off.crowd, off.ids[i], &point, &following, &glances),
              "cg_crowd_read_following");
        require(following == 0 && glances == 0, "no one follows with follow_enabled 0");
    }
    printf("follow_enabled 0 and a %u-byte config: bit-identical over %d frames\n",
           (unsigned)CONFIG_SIZE_BEFORE_STREET, FPS * SECONDS);
    cg_crowd_destroy(off.crowd);
    cg_crowd_destroy(old.crowd);
}

int main(void) {
    require(CONFIG_SIZE_BEFORE_STREET == 216, "the older layout is 216 bytes");
    followers();
    off_by_default();
    puts("ok");
    return 0;
}
