/* pauses_and_fork.c: two promises of cg_crowd_step seen from C.
 *
 * 1. Any finite dt returns: a time stamp passed as a step (3e8 s, 1.7e9 s), the largest
 *    float, each on a crowd that blinks, talks in groups and runs every attention model, on
 *    one thread and on two; every output stays finite and the crowd goes on blinking.
 * 2. A crowd with worker threads (config.threads = 2) stepped in a child after fork():
 *    the child's step returns and gives the same gaze and joints as the parent's step of
 *    the same crowd.
 *
 * alarm() turns a hang into a failure: the program is killed by SIGALRM after 300 s (room for valgrind). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "crowdgaze.h"

#define CHARACTERS 40
#define FPS 30.0f

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

typedef struct {
    cg_crowd *crowd;
    cg_entity_state states[CHARACTERS];
    double time;
} street;

/* CHARACTERS people on a line, every third on another attention model, pairs of the
 * first twelve talking in groups, half of them walking. */
static void street_init(street *s, uint32_t threads) {
    cg_crowd_config config;
    uint32_t i;
    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "config_init");
    config.threads = threads;
    config.seed = 5;
    ok(cg_crowd_create(&config, &s->crowd), "create");
    for (i = 0; i < CHARACTERS; i++) {
        cg_character_desc desc;
        cg_character_params params;
        desc.struct_size = sizeof desc;
        ok(cg_character_desc_init(&desc), "desc_init");
        desc.position = (cg_vec3){(float)(i % 8), 0.0f, (float)(i / 8) * 2.0f};
        s->states[i].struct_size = sizeof s->states[i];
        ok(cg_entity_state_init(&s->states[i]), "state_init");
        ok(cg_crowd_add_character(s->crowd, &desc, &s->states[i].id), "add_character");
        s->states[i].position = desc.position;
        s->states[i].flags = CG_STATE_HEADING_FROM_MOTION | (i < 12 && i % 2 ? CG_STATE_TALKING : 0);
        params.struct_size = sizeof params;
        ok(cg_crowd_get_character_params(s->crowd, s->states[i].id, &params), "get_params");
        params.attention_model = (cg_attention_model)(i % 3);
        ok(cg_crowd_set_character_params(s->crowd, s->states[i].id, &params), "set_params");
    }
    for (i = 0; i < 12; i += 2) {
        uint32_t members[2] = {s->states[i].id, s->states[i + 1].id}, group;
        ok(cg_crowd_set_conversation(s->crowd, members, 2, &group), "set_conversation");
    }
    s->time = 0.0;
}

/* Pushes the walkers one frame on (unless `still`) and steps by `dt`. */
static void street_step(street *s, float dt, int still) {
    uint32_t i;
    s->time += still ? (double)dt : 1.0 / FPS;
    for (i = 0; i < CHARACTERS; i++)
        if (!still && i % 2 == 0) s->states[i].position.x += 1.4f / FPS;
    ok(cg_crowd_push_frame(s->crowd, s->time, s->states, CHARACTERS), "push_frame");
    ok(cg_crowd_step(s->crowd, dt), "step");
}

/* Every character's gaze, eyelids and joints, as floats, into `out` (returns the count). */
static size_t outputs(cg_crowd *crowd, float *out, size_t room) {
    cg_gaze_info gaze[CHARACTERS];
    cg_eyelids lids[CHARACTERS];
    cg_quat joints[CHARACTERS * 16];
    size_t n = 0, i, total;
    ok(cg_crowd_read_gaze(crowd, gaze, CHARACTERS, NULL), "read_gaze");
    ok(cg_crowd_read_eyelids(crowd, 0, CHARACTERS, lids, CHARACTERS), "read_eyelids");
    ok(cg_crowd_joint_total(crowd, 0, CHARACTERS, &total), "joint_total");
    if (total > CHARACTERS * 16) exit(1);
    ok(cg_crowd_read_joints(crowd, 0, CHARACTERS, joints, total), "read_joints");
    for (i = 0; i < CHARACTERS && n + 7 <= room; i++) {
        out[n++] = gaze[i].target_position.x;
        out[n++] = gaze[i].target_position.y;
        out[n++] = gaze[i].target_position.z;
        out[n++] = gaze[i].attentive_fraction;
        out[n++] = (float)gaze[i].target;
        out[n++] = lids[i].left_closure;
        out[n++] = lids[i].left_lid_pitch;
    }
    for (i = 0; i < total && n + 4 <= room; i++) {
        out[n++] = joints[i].x;
        out[n++] = joints[i].y;
        out[n++] = joints[i].z;
        out[n++] = joints[i].w;
    }
    return n;
}

static int all_finite(const float *values, size_t n) {
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(values[i])) return 0;
    return 1;
}

#define ROOM (CHARACTERS * 7 + CHARACTERS * 16 * 4)
static float before_fork[ROOM], parent_out[ROOM], child_out[ROOM];

/* Frames after the long steps: 150, or 60 under valgrind (scripts/memcheck sets
 * CG_EXAMPLE_SECONDS for its slow runs). */
static int frames_after = 150;

static void long_steps(uint32_t threads) {
    static const float steps[] = {1e4f, 3e8f, 1.7e9f, 3.4028235e38f};
    size_t k;
    for (k = 0; k < sizeof steps / sizeof steps[0]; k++) {
        street s;
        int frame, closed_frames = 0;
        size_t n;
        street_init(&s, threads);
        for (frame = 0; frame < 20; frame++) street_step(&s, 1.0f / FPS, 0);
        street_step(&s, steps[k], 1);
        street_step(&s, steps[k], 1);
        n = outputs(s.crowd, parent_out, ROOM);
        CHECK(all_finite(parent_out, n));
        /* Normal frames afterwards: lids close again. */
        for (frame = 0; frame < frames_after; frame++) {
            cg_eyelids lids[CHARACTERS];
            int i, closed = 0;
            street_step(&s, 1.0f / FPS, 0);
            ok(cg_crowd_read_eyelids(s.crowd, 0, CHARACTERS, lids, CHARACTERS), "read_eyelids");
            for (i = 0; i < CHARACTERS; i++) closed |= lids[i].left_closure > 0.0f;
            closed_frames += closed;
        }
        n = outputs(s.crowd, parent_out, ROOM);
        CHECK(all_finite(parent_out, n));
        CHECK(closed_frames > 20);
        printf("dt %g on %u thread(s): returned, finite, blinking in %d of %d frames after\n",
               (double)steps[k], threads, closed_frames, frames_after);
        cg_crowd_destroy(s.crowd);
    }
}

static void forked_step(void) {
    street s;
    int frame, fds[2], status;
    size_t n, got = 0;
    pid_t child;
    street_init(&s, 2);
    for (frame = 0; frame < 30; frame++) street_step(&s, 1.0f / FPS, 0);
    (void)outputs(s.crowd, before_fork, ROOM);
    if (pipe(fds) != 0) exit(1);
    fflush(stdout);
    child = fork();
    if (child < 0) exit(1);
    if (child == 0) {
        /* The child: the workers stayed in the parent. */
        close(fds[0]);
        for (frame = 0; frame < 10; frame++) street_step(&s, 1.0f / FPS, 0);
        n = outputs(s.crowd, child_out, ROOM);
        if (write(fds[1], child_out, n * sizeof(float)) != (ssize_t)(n * sizeof(float))) _exit(3);
        cg_crowd_destroy(s.crowd);
        _exit(0);
    }
    close(fds[1]);
    for (frame = 0; frame < 10; frame++) street_step(&s, 1.0f / FPS, 0);
    n = outputs(s.crowd, parent_out, ROOM);
    for (;;) {
        ssize_t r = read(fds[0], (char *)child_out + got, sizeof child_out - got);
        if (r <= 0) break;
        got += (size_t)r;
    }
    close(fds[0]);
    CHECK(waitpid(child, &status, 0) == child && WIFEXITED(status) && WEXITSTATUS(status) == 0);
    CHECK(got == n * sizeof(float));
    CHECK(memcmp(parent_out, child_out, n * sizeof(float)) == 0);
    CHECK(memcmp(parent_out, before_fork, n * sizeof(float)) != 0); /* the steps moved */
    printf("forked child on 2 threads: %zu outputs equal to the parent's\n", n);
    cg_crowd_destroy(s.crowd);
}

int main(void) {
    if (getenv("CG_EXAMPLE_SECONDS") != NULL) frames_after = 60;
    alarm(300);
    long_steps(1);
    long_steps(2);
    forked_step();
    if (failures) {
        fprintf(stderr, "%d failures\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
