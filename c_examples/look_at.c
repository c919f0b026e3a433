/* look_at.c: one character with the human gaze chain (5 spine, 2 neck, head, 2 eyes) looks
 * at a point. First the point jumps 60 degrees to the left: the eyes lead, the head follows,
 * the torso comes last and the eyes re-centre in the head. Then the point circles the
 * character at 2 m. Prints the eye, head and torso yaw (degrees) against time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "crowdgaze.h"

#define FPS 30
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

static cg_quat multiply(cg_quat a, cg_quat b) {
    cg_quat r;
    r.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    r.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    r.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    r.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return r;
}

/* Yaw (degrees, counter-clockwise about +Y from +Z) of +Z rotated by q. */
static float yaw_of(cg_quat q) {
    /* q * (0, 0, 1): the third column of the rotation matrix. */
    float x = 2.0f * (q.x * q.z + q.w * q.y);
    float z = 1.0f - 2.0f * (q.x * q.x + q.y * q.y);
    return atan2f(x, z) * 180.0f / PI_F;
}

typedef struct {
    float torso, head, eyes;
} yaws;

/* Accumulates the human chain's local rotations (rest identity) bottom to top. */
static yaws read_yaws(const cg_crowd *crowd) {
    cg_quat joints[10];
    cg_quat world = {0.0f, 0.0f, 0.0f, 1.0f};
    yaws out;
    int i;
    ok(cg_crowd_read_joints(crowd, 0, 1, joints, 10), "cg_crowd_read_joints");
    for (i = 0; i < 5; i++) world = multiply(world, joints[i]);
    out.torso = yaw_of(world);
    for (i = 5; i < 8; i++) world = multiply(world, joints[i]);
    out.head = yaw_of(world);
    out.eyes = 0.5f * (yaw_of(multiply(world, joints[8])) + yaw_of(multiply(world, joints[9])));
    return out;
}

int main(void) {
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    cg_character_desc desc;
    cg_gaze_target target;
    uint32_t id;
    size_t joints = 0;
    int frame;
    float eye_onset = -1, head_onset = -1, torso_onset = -1;
    float eye_arrive = -1, head_arrive = -1, torso_arrive = -1;
    float final_eye_in_head = 0.0f, peak_eye_in_head = 0.0f;
    const float goal = 60.0f;

    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "config");
    config.max_characters = 1;
    config.max_objects = 0;
    ok(cg_crowd_create(&config, &crowd), "create");
    desc.struct_size = sizeof desc;
    ok(cg_character_desc_init(&desc), "desc");
    ok(cg_crowd_add_character(crowd, &desc, &id), "add");
    ok(cg_crowd_joint_total(crowd, 0, 1, &joints), "joint total");
    CHECK(joints == 10);

    /* 1. A jump of 60 degrees to the left (Y up, +Z forward: left is +X), at eye height. */
    target.struct_size = sizeof target;
    ok(cg_gaze_target_init(&target), "target");
    target.point.x = 3.0f * sinf(goal * PI_F / 180.0f);
    target.point.y = 1.6f;
    target.point.z = 3.0f * cosf(goal * PI_F / 180.0f);
    ok(cg_crowd_set_gaze_target(crowd, id, &target), "set target");
    printf("gaze shift to %.0f degrees\n   t     eyes   head  torso\n", goal);
    for (frame = 1; frame <= 3 * FPS; frame++) {
        float t = (float)frame / FPS;
        yaws y;
        ok(cg_crowd_step(crowd, 1.0f / FPS), "step");
        y = read_yaws(crowd);
        if (frame % 3 == 0) printf("%5.2f  %5.1f  %5.1f  %5.1f\n", t, y.eyes, y.head, y.torso);
        if (eye_onset < 0 && y.eyes > 1.0f) eye_onset = t;
        if (head_onset < 0 && y.head > 1.0f) head_onset = t;
        if (torso_onset < 0 && y.torso > 1.0f) torso_onset = t;
        if (eye_arrive < 0 && y.eyes > goal - 1.0f) eye_arrive = t;
        if (head_arrive < 0 && y.head > 0.98f * 45.0f) head_arrive = t;
        if (torso_arrive < 0 && y.torso > 0.98f * 30.0f) torso_arrive = t;
        if (y.eyes - y.head > peak_eye_in_head) peak_eye_in_head = y.eyes - y.head;
        final_eye_in_head = y.eyes - y.head;
    }
    printf("onset: eyes %.2f s, head %.2f s, torso %.2f s\n", eye_onset, head_onset, torso_onset);
    printf("arrival: eyes %.2f s, head %.2f s, torso %.2f s\n", eye_arrive, head_arrive,
           torso_arrive);
    printf("eyes in head: peak %.1f, final %.1f degrees\n", peak_eye_in_head, final_eye_in_head);
    CHECK(eye_onset > 0 && head_onset > 0 && torso_onset > 0);
    CHECK(eye_onset <= head_onset && head_onset <= torso_onset);
    CHECK(eye_arrive > 0 && head_arrive > 0 && torso_arrive > 0);
    CHECK(eye_arrive <= head_arrive && head_arrive <= torso_arrive);
    CHECK(peak_eye_in_head > 20.0f);
    CHECK(fabsf(final_eye_in_head) < peak_eye_in_head * 0.75f);

    /* 2. The point circles the character at 2 m, once in 12 s. */
    printf("circling target\n   t   target   eyes   head  torso\n");
    for (frame = 1; frame <= 12 * FPS; frame++) {
        float t = (float)frame / FPS;
        float angle = goal + 360.0f * t / 12.0f;
        yaws y;
        target.point.x = 2.0f * sinf(angle * PI_F / 180.0f);
        target.point.z = 2.0f * cosf(angle * PI_F / 180.0f);
        ok(cg_crowd_set_gaze_target(crowd, id, &target), "move target");
        ok(cg_crowd_step(crowd, 1.0f / FPS), "step");
        y = read_yaws(crowd);
        if (frame % 30 == 0) {
            float wrapped = fmodf(angle + 180.0f, 360.0f) - 180.0f;
            printf("%5.2f  %6.1f  %5.1f  %5.1f  %5.1f\n", t, wrapped, y.eyes, y.head, y.torso);
        }
        CHECK(y.eyes == y.eyes && y.head == y.head && y.torso == y.torso); /* no NaN */
    }

    ok(cg_crowd_clear_gaze_target(crowd, id), "clear");
    cg_crowd_destroy(crowd);
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
