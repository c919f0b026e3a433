/* job_ranges.c: pushing and stepping a crowd from an engine's own worker threads.
 *
 * Each frame: cg_crowd_begin_push once, then four POSIX threads (standing in for a job
 * system's workers) take parts of 64 entity states until none is left and call
 * cg_crowd_push_range on them concurrently, then cg_crowd_end_push; the same for the step:
 * cg_crowd_begin_step, ranges of 64 characters through cg_crowd_step_range, then
 * cg_crowd_end_step. A second crowd with the same seed and inputs is pushed with the
 * one-call cg_crowd_push_frame and stepped with cg_crowd_step, and a third stepped with
 * cg_crowd_step on two internal threads (config.threads = 2): all three must give
 * bit-identical gaze and joints every frame. Also shows the misuse errors. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "crowdgaze.h"

#define CHARACTERS 1000
#define WORKERS 4
#define RANGE 64
#define FRAMES 60
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

/* A job queue of ranges: the next range's first character, taken under a mutex (a real
 * engine would use its own queue or an atomic counter). */
typedef struct {
    cg_crowd *crowd;
    const cg_entity_state *states; /* the frame's states, for the push's jobs */
    pthread_mutex_t lock;
    uint32_t next;
    uint32_t count;
    int errors;
} job_queue;

/* Takes the next job's first index, or returns 0 when none is left. */
static int next_job(job_queue *queue, uint32_t *first, uint32_t *count) {
    pthread_mutex_lock(&queue->lock);
    *first = queue->next;
    queue->next += RANGE;
    pthread_mutex_unlock(&queue->lock);
    if (*first >= queue->count) return 0;
    *count = queue->count - *first < RANGE ? queue->count - *first : RANGE;
    return 1;
}

static void count_error(job_queue *queue, cg_status status) {
    if (status != CG_STATUS_OK) {
        pthread_mutex_lock(&queue->lock);
        queue->errors++;
        pthread_mutex_unlock(&queue->lock);
    }
}

/* A push job: a part of the frame's states. */
static void *push_worker(void *argument) {
    job_queue *queue = (job_queue *)argument;
    uint32_t first, count;
    while (next_job(queue, &first, &count)) {
        /* May run on several threads at once, each with its own entities. */
        count_error(queue, cg_crowd_push_range(queue->crowd, queue->states + first, count));
    }
    return NULL;
}

/* A step job: a range of characters. */
static void *worker(void *argument) {
    job_queue *queue = (job_queue *)argument;
    uint32_t first, count;
    while (next_job(queue, &first, &count)) {
        /* May run on several threads at once, on disjoint ranges. */
        count_error(queue, cg_crowd_step_range(queue->crowd, first, count));
    }
    return NULL;
}

static cg_crowd *make_crowd(uint32_t threads, cg_entity_state *states) {
    cg_crowd_config config;
    cg_character_desc desc;
    cg_crowd *crowd = NULL;
    uint32_t i;
    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "config");
    config.max_characters = CHARACTERS;
    config.threads = threads;
    ok(cg_crowd_create(&config, &crowd), "create");
    desc.struct_size = sizeof desc;
    ok(cg_character_desc_init(&desc), "desc");
    for (i = 0; i < CHARACTERS; i++) {
        /* 1000 people on a 50 m x 80 m street, 0.25 per square metre. */
        desc.position.x = (float)(i % 25) * 2.0f;
        desc.position.z = (float)(i / 25) * 2.0f;
        desc.heading = (float)(i % 7) * 0.9f;
        ok(cg_crowd_add_character(crowd, &desc, &states[i].id), "add");
    }
    return crowd;
}

/* Walks everyone: odd columns one way, even columns the other. */
static void move(cg_entity_state *states, int frame) {
    uint32_t i;
    for (i = 0; i < CHARACTERS; i++) {
        float direction = (i % 2) ? 1.0f : -1.0f;
        states[i].position.x = (float)(i % 25) * 2.0f;
        states[i].position.z = (float)(i / 25) * 2.0f + direction * 1.3f * (float)frame / FPS;
    }
}

static void snapshot(const cg_crowd *crowd, cg_gaze_info *gaze, cg_quat *joints,
                     size_t joint_total) {
    size_t written = 0;
    ok(cg_crowd_read_gaze(crowd, gaze, CHARACTERS, &written), "read gaze");
    CHECK(written == CHARACTERS);
    ok(cg_crowd_read_joints(crowd, 0, CHARACTERS, joints, joint_total), "read joints");
}

int main(void) {
    static cg_entity_state states[3][CHARACTERS];
    static cg_gaze_info gaze[3][CHARACTERS];
    cg_crowd *crowds[3];
    cg_quat *joints[3];
    size_t joint_total = 0;
    int frame, c, attending = 0;
    job_queue queue;

    for (c = 0; c < 3; c++) {
        uint32_t i;
        for (i = 0; i < CHARACTERS; i++) {
            states[c][i].struct_size = sizeof states[c][i];
            ok(cg_entity_state_init(&states[c][i]), "state");
            states[c][i].flags = CG_STATE_HEADING_FROM_MOTION;
        }
        crowds[c] = make_crowd(c == 2 ? 2 : 1, states[c]);
    }
    ok(cg_crowd_joint_total(crowds[0], 0, CHARACTERS, &joint_total), "joint total");
    for (c = 0; c < 3; c++) {
        joints[c] = (cg_quat *)malloc(joint_total * sizeof(cg_quat));
        if (!joints[c]) return 1;
    }

    /* Misuse is an error, never a crash. */
    CHECK(cg_crowd_step_range(crowds[0], 0, 10) == CG_STATUS_WRONG_STATE);
    CHECK(cg_crowd_end_step(crowds[0]) == CG_STATUS_WRONG_STATE);

    CHECK(cg_crowd_push_range(crowds[0], states[0], 10) == CG_STATUS_WRONG_STATE);
    CHECK(cg_crowd_end_push(crowds[0]) == CG_STATUS_WRONG_STATE);

    queue.crowd = crowds[0];
    queue.states = states[0];
    queue.count = CHARACTERS;
    queue.errors = 0;
    pthread_mutex_init(&queue.lock, NULL);
    for (frame = 1; frame <= FRAMES; frame++) {
        pthread_t threads[WORKERS];
        int w;
        for (c = 0; c < 3; c++) move(states[c], frame);
        /* Crowd 0: the engine's workers push parts of the frame. */
        ok(cg_crowd_begin_push(crowds[0], frame / FPS), "begin push");
        CHECK(cg_crowd_step(crowds[0], 1.0f / FPS) == CG_STATUS_WRONG_STATE);
        queue.next = 0;
        for (w = 0; w < WORKERS; w++) pthread_create(&threads[w], NULL, push_worker, &queue);
        for (w = 0; w < WORKERS; w++) pthread_join(threads[w], NULL);
        /* Each entity once per push: a second state for one is refused. */
        CHECK(cg_crowd_push_range(crowds[0], states[0], 1) == CG_STATUS_WRONG_STATE);
        ok(cg_crowd_end_push(crowds[0]), "end push");
        for (c = 1; c < 3; c++) {
            ok(cg_crowd_push_frame(crowds[c], frame / FPS, states[c], CHARACTERS), "push");
        }
        /* Crowd 0: the engine's workers step ranges. */
        ok(cg_crowd_begin_step(crowds[0], 1.0f / FPS), "begin step");
        CHECK(cg_crowd_read_gaze(crowds[0], gaze[0], CHARACTERS, NULL) ==
              CG_STATUS_WRONG_STATE);
        queue.next = 0;
        for (w = 0; w < WORKERS; w++) pthread_create(&threads[w], NULL, worker, &queue);
        for (w = 0; w < WORKERS; w++) pthread_join(threads[w], NULL);
        CHECK(cg_crowd_step_range(crowds[0], 0, 1) == CG_STATUS_WRONG_STATE); /* taken */
        ok(cg_crowd_end_step(crowds[0]), "end step");
        /* Crowd 1: one call. Crowd 2: one call on two internal threads. */
        ok(cg_crowd_step(crowds[1], 1.0f / FPS), "step");
        ok(cg_crowd_step(crowds[2], 1.0f / FPS), "step on two threads");
        for (c = 0; c < 3; c++) snapshot(crowds[c], gaze[c], joints[c], joint_total);
        for (c = 1; c < 3; c++) {
            CHECK(memcmp(gaze[0], gaze[c], sizeof gaze[0]) == 0);
            CHECK(memcmp(joints[0], joints[c], joint_total * sizeof(cg_quat)) == 0);
        }
    }
    CHECK(queue.errors == 0);
    for (c = 0; c < CHARACTERS; c++) attending += gaze[0][c].attending ? 1 : 0;
    CHECK(attending > 0);
    printf("%d frames of %d characters pushed and stepped by %d threads in ranges of %d:\n"
           "identical to cg_crowd_step on 1 and 2 threads; %d characters attending.\n",
           FRAMES, CHARACTERS, WORKERS, RANGE, attending);

    pthread_mutex_destroy(&queue.lock);
    for (c = 0; c < 3; c++) {
        free(joints[c]);
        cg_crowd_destroy(crowds[c]);
    }
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
