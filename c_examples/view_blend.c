/* view_blend.c: view-adaptive animation (Chaudhuri, Papagiannakis & Magnenat-Thalmann) from C.
 *
 * A character (y up, facing +z) has three key animations: it turns, looks and gestures to its
 * left, to the front and to its right. Each has one key camera in that direction. A viewer
 * orbits the character; at each position the example prints the view weights and the head's
 * blended rotation with DLB and with DIB side by side, and checks that the weights sum to 1,
 * that a viewer on a key camera gets that key alone, and that DLB and DIB agree closely.
 * It also recovers a viewer position from a 3x4 camera matrix P = K[R|t]. */
#include <math.h>
#include <stdio.h>

#include "crowdgaze.h"

#define JOINTS 5   /* pelvis, spine, head, right shoulder, right elbow */
#define KEYS 3     /* left, front, right */
#define FRAMES 20  /* a 2 s loop at 10 fps */
#define HEAD 2

static const float PI = 3.14159265358979f;
static int failures = 0;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);    \
            failures++;                                                                  \
        }                                                                                \
    } while (0)

/* Stops with the library's message if a call fails. */
static int ok_or_report(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s failed: %s (%s)\n", what, cg_status_str(status), message);
        failures++;
        return 0;
    }
    return 1;
}

static cg_quat axis_angle(float x, float y, float z, float angle) {
    float s = sinf(angle / 2.0f);
    cg_quat q;
    q.x = x * s;
    q.y = y * s;
    q.z = z * s;
    q.w = cosf(angle / 2.0f);
    return q;
}

static cg_quat multiply(cg_quat a, cg_quat b) {
    cg_quat q;
    q.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    q.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    q.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    q.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return q;
}

static cg_vec3 vec3(float x, float y, float z) {
    cg_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static cg_dualquat joint(cg_quat rotation, cg_vec3 offset) {
    cg_dualquat q;
    ok_or_report(cg_dualquat_from_rt(&rotation, &offset, &q), "cg_dualquat_from_rt");
    return q;
}

/* Key animation `side` (+1 left, 0 front, -1 right), frame f: the body turns towards that
 * side (pelvis 20°, spine 25°, head 35°), the head nods a little, and the right arm rises
 * towards that side and waves. Local joint transforms. */
static void key_frame(float side, int f, cg_dualquat *pose) {
    float phase = 2.0f * PI * (float)f / (float)FRAMES;
    float degree = PI / 180.0f;
    float nod = 5.0f * degree * sinf(phase);
    float raise = (60.0f + 15.0f * sinf(phase)) * degree;
    pose[0] = joint(axis_angle(0, 1, 0, side * 20.0f * degree), vec3(0.0f, 1.0f, 0.0f));
    pose[1] = joint(axis_angle(0, 1, 0, side * 25.0f * degree), vec3(0.0f, 0.3f, 0.0f));
    pose[2] = joint(multiply(axis_angle(0, 1, 0, side * 35.0f * degree), axis_angle(1, 0, 0, nod)),
                    vec3(0.0f, 0.35f, 0.0f));
    pose[3] = joint(multiply(axis_angle(0, 1, 0, side * 45.0f * degree),
                             axis_angle(0, 0, 1, -raise)),
                    vec3(-0.2f, 0.25f, 0.0f));
    pose[4] = joint(axis_angle(0, 0, 1, -0.5f * raise), vec3(-0.3f, 0.0f, 0.0f));
}

static cg_view_blender *make_blender(cg_blend_method method, const cg_vec3 *cameras) {
    cg_view_blender_config config;
    cg_view_blender *blender = NULL;
    static cg_dualquat frames[FRAMES * JOINTS];
    uint32_t key;
    int f;
    config.struct_size = sizeof config;
    cg_view_blender_config_init(&config);
    config.joint_count = JOINTS;
    config.key_count = KEYS;
    config.alpha = 2.0f;
    config.distance = CG_VIEW_DISTANCE_GEODESIC;
    config.method = method;
    config.precision = 1e-6f;
    config.max_iterations = 16;
    if (!ok_or_report(cg_view_blender_create(&config, &blender), "cg_view_blender_create")) {
        return NULL;
    }
    for (key = 0; key < KEYS; key++) {
        float side = 1.0f - (float)key; /* left, front, right */
        for (f = 0; f < FRAMES; f++) {
            key_frame(side, f, &frames[f * JOINTS]);
        }
        ok_or_report(cg_view_blender_set_key_clip(blender, key, frames, FRAMES, 10.0f, true),
                     "cg_view_blender_set_key_clip");
        ok_or_report(cg_view_blender_add_camera(blender, cameras[key], key),
                     "cg_view_blender_add_camera");
    }
    return blender;
}

static float yaw_degrees(cg_quat q) {
    /* The rotation's angle about y (its y-axis twist). */
    return 2.0f * atan2f(q.y, q.w) * 180.0f / PI;
}

int main(void) {
    const float sin60 = 0.8660254f, cos60 = 0.5f;
    cg_vec3 cameras[KEYS];
    cg_view_blender *dlb, *dib;
    cg_dualquat character, pose_dlb[JOINTS], pose_dib[JOINTS];
    cg_quat heading = axis_angle(0, 1, 0, 30.0f * PI / 180.0f);
    cg_vec3 position = vec3(2.0f, 0.0f, 5.0f);
    float worst_difference = 0.0f;
    int step, key, i;

    /* Key cameras in the character's frame: 60° to its left (+x), front (+z), 60° right. */
    cameras[0] = vec3(sin60, 0.0f, cos60);
    cameras[1] = vec3(0.0f, 0.0f, 1.0f);
    cameras[2] = vec3(-sin60, 0.0f, cos60);

    dlb = make_blender(CG_BLEND_METHOD_DLB, cameras);
    dib = make_blender(CG_BLEND_METHOD_DIB, cameras);
    if (dlb == NULL || dib == NULL) {
        return 1;
    }
    /* The character stands at (2, 0, 5), turned 30° about y. */
    ok_or_report(cg_dualquat_from_rt(&heading, &position, &character), "cg_dualquat_from_rt");

    printf("viewer angle | weights left front right | head yaw DLB (x y z w)            "
           "| head yaw DIB (x y z w)\n");
    for (step = -6; step <= 6; step++) {
        /* The viewer orbits at 3 m, eyes at 1.6 m, from 90° right to 90° left. */
        float angle = (float)step * 15.0f * PI / 180.0f;
        cg_vec3 local = vec3(3.0f * sinf(angle), 1.6f, 3.0f * cosf(angle));
        cg_vec3 viewer;
        float weights[KEYS], total = 0.0f, difference = 0.0f;
        double t = 0.1 * (double)(step + 6);
        float matrix[16];
        /* World position: the character's transform applied to the local offset. */
        ok_or_report(cg_dualquat_to_matrix(&character, matrix), "cg_dualquat_to_matrix");
        viewer.x = matrix[0] * local.x + matrix[4] * local.y + matrix[8] * local.z + matrix[12];
        viewer.y = matrix[1] * local.x + matrix[5] * local.y + matrix[9] * local.z + matrix[13];
        viewer.z = matrix[2] * local.x + matrix[6] * local.y + matrix[10] * local.z + matrix[14];

        ok_or_report(cg_view_blender_weights(dlb, &character, &viewer, weights, KEYS),
                     "cg_view_blender_weights");
        ok_or_report(cg_view_blender_evaluate(dlb, &character, &viewer, t, pose_dlb, JOINTS),
                     "cg_view_blender_evaluate (DLB)");
        ok_or_report(cg_view_blender_evaluate(dib, &character, &viewer, t, pose_dib, JOINTS),
                     "cg_view_blender_evaluate (DIB)");
        for (key = 0; key < KEYS; key++) {
            total += weights[key];
            CHECK(weights[key] >= 0.0f && weights[key] <= 1.0f);
        }
        CHECK(fabsf(total - 1.0f) < 1e-5f);
        for (i = 0; i < JOINTS; i++) {
            const float *a = &pose_dlb[i].real.x, *b = &pose_dib[i].real.x;
            float dot = fabsf(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
            float d = 2.0f * acosf(dot < 1.0f ? dot : 1.0f) * 180.0f / PI;
            if (d > difference) {
                difference = d;
            }
        }
        if (difference > worst_difference) {
            worst_difference = difference;
        }
        printf("%+5.0f deg    | %.3f %.3f %.3f          | %+6.2f deg (%+.4f %+.4f %+.4f %+.4f) "
               "| %+6.2f deg (%+.4f %+.4f %+.4f %+.4f)\n",
               (double)(angle * 180.0f / PI), (double)weights[0], (double)weights[1],
               (double)weights[2], (double)yaw_degrees(pose_dlb[HEAD].real),
               (double)pose_dlb[HEAD].real.x, (double)pose_dlb[HEAD].real.y,
               (double)pose_dlb[HEAD].real.z, (double)pose_dlb[HEAD].real.w,
               (double)yaw_degrees(pose_dib[HEAD].real), (double)pose_dib[HEAD].real.x,
               (double)pose_dib[HEAD].real.y, (double)pose_dib[HEAD].real.z,
               (double)pose_dib[HEAD].real.w);
    }
    /* DLB and DIB agree within 1° for every joint (DIB is the exact mean; DLB is close). */
    printf("largest angle between DLB and DIB rotations, all joints: %.2f deg\n",
           (double)worst_difference);
    CHECK(worst_difference < 1.0f);

    /* A viewer exactly on each key camera, at any range, gets that key alone. */
    for (key = 0; key < KEYS; key++) {
        float matrix[16], weights[KEYS];
        cg_vec3 local = vec3(cameras[key].x * 7.0f, cameras[key].y * 7.0f, cameras[key].z * 7.0f);
        cg_vec3 viewer;
        ok_or_report(cg_dualquat_to_matrix(&character, matrix), "cg_dualquat_to_matrix");
        viewer.x = matrix[0] * local.x + matrix[4] * local.y + matrix[8] * local.z + matrix[12];
        viewer.y = matrix[1] * local.x + matrix[5] * local.y + matrix[9] * local.z + matrix[13];
        viewer.z = matrix[2] * local.x + matrix[6] * local.y + matrix[10] * local.z + matrix[14];
        ok_or_report(cg_view_blender_weights(dlb, &character, &viewer, weights, KEYS),
                     "cg_view_blender_weights");
        printf("on key camera %d: weights %.3f %.3f %.3f\n", key, (double)weights[0],
               (double)weights[1], (double)weights[2]);
        for (i = 0; i < KEYS; i++) {
            CHECK(weights[i] == (i == key ? 1.0f : 0.0f));
        }
    }

    /* A viewer at the character's centre has no direction: an error, not a NaN. */
    {
        float weights[KEYS] = {0.5f, 0.5f, 0.5f};
        CHECK(cg_view_blender_weights(dlb, &character, &position, weights, KEYS) ==
              CG_STATUS_INVALID_ARGUMENT);
        CHECK(weights[0] == 0.5f);
    }

    /* The viewer from camera tracking: P = K[R|t] with the camera at (4, 1.6, 1), R = I,
     * so t = -C; P is row-major. */
    {
        const float f = 800.0f, cx = 320.0f, cy = 240.0f;
        cg_vec3 centre = vec3(4.0f, 1.6f, 1.0f), found;
        float p[12];
        p[0] = f;    p[1] = 0.0f; p[2] = cx;    p[3] = -(f * centre.x + cx * centre.z);
        p[4] = 0.0f; p[5] = f;    p[6] = cy;    p[7] = -(f * centre.y + cy * centre.z);
        p[8] = 0.0f; p[9] = 0.0f; p[10] = 1.0f; p[11] = -centre.z;
        ok_or_report(cg_camera_center_from_projection(p, &found),
                     "cg_camera_center_from_projection");
        printf("camera centre from P: (%.3f, %.3f, %.3f)\n", (double)found.x, (double)found.y,
               (double)found.z);
        CHECK(fabsf(found.x - centre.x) < 1e-3f && fabsf(found.y - centre.y) < 1e-3f &&
              fabsf(found.z - centre.z) < 1e-3f);
    }

    cg_view_blender_destroy(dlb);
    cg_view_blender_destroy(dib);
    if (failures != 0) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
