/* models.c: the same street scene (street_scene.h: 130 characters, 60 objects) run for 60 s
 * with each attention model — the crowd model (Grillon & Thalmann 2009), the saliency model
 * (Kokkinara, Oyekoya & Steed 2011) and the stock baseline. Prints per model: gaze shifts
 * per minute (eyes and head), the share of time the eyes spend on characters, on objects
 * and ahead, the mean eye-in-head eccentricity, and the mean eye fixation length. */
#include <math.h>
#include <string.h>

#include "street_scene.h"

#define CHARACTERS 130
#define OBJECTS 60
#define FPS 30
#define SECONDS 60 /* simulated; CG_EXAMPLE_SECONDS overrides (scripts/memcheck's valgrind run) */
#define JOINTS 10 /* the human chain: 5 spine, 2 neck, head, 2 eyes */

typedef struct {
    double eye_shifts, head_shifts;
    double on_characters, on_objects, ahead, samples;
    double eccentricity;
} model_stats;

/* Simulated seconds per model: SECONDS, or the environment's CG_EXAMPLE_SECONDS if set. */
static int seconds(void) {
    const char *text = getenv("CG_EXAMPLE_SECONDS");
    int value = text ? atoi(text) : 0;
    return value > 0 ? value : SECONDS;
}

static int is_character(const uint32_t *ids, uint32_t id) {
    int i;
    for (i = 0; i < CHARACTERS; i++)
        if (ids[i] == id) return 1;
    return 0;
}

/* Angle (degrees) of a unit quaternion's rotation. */
static double rotation_degrees(cg_quat q) {
    double w = fabs((double)q.w);
    if (w > 1.0) w = 1.0;
    return 2.0 * acos(w) * 180.0 / 3.14159265358979;
}

static model_stats run(uint32_t model) {
    static street_person people[CHARACTERS];
    static cg_entity_state states[CHARACTERS];
    static uint32_t ids[CHARACTERS];
    static cg_gaze_info gaze[CHARACTERS];
    static uint32_t last_eye[CHARACTERS], last_part[CHARACTERS], last_head[CHARACTERS];
    static cg_quat joints[CHARACTERS * JOINTS];
    street_scene scene;
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    model_stats stats;
    int i, frame;
    size_t written, total = 0;

    memset(&stats, 0, sizeof stats);
    config.struct_size = sizeof config;
    street_check(cg_crowd_config_init(&config), "config");
    config.seed = 2011;
    config.max_characters = CHARACTERS;
    config.max_objects = OBJECTS;
    street_check(cg_crowd_create(&config, &crowd), "create");
    scene.people = people;
    scene.states = states;
    scene.ids = ids;
    street_populate(&scene, crowd, CHARACTERS, OBJECTS, model);
    street_check(cg_crowd_joint_total(crowd, 0, CHARACTERS, &total), "joint total");
    if (total != CHARACTERS * JOINTS) {
        fprintf(stderr, "unexpected joint total %zu\n", total);
        exit(1);
    }
    for (i = 0; i < CHARACTERS; i++) last_eye[i] = last_head[i] = last_part[i] = CG_NO_TARGET;

    for (frame = 1; frame <= FPS * seconds(); frame++) {
        const float dt = 1.0f / FPS;
        street_advance(&scene, crowd, frame * (double)dt, dt);
        street_check(cg_crowd_step(crowd, dt), "step");
        street_check(cg_crowd_read_gaze(crowd, gaze, CHARACTERS, &written), "read gaze");
        street_check(cg_crowd_read_joints(crowd, 0, CHARACTERS, joints, total), "read joints");
        for (i = 0; i < CHARACTERS; i++) {
            const cg_gaze_info *g = &gaze[i];
            if (g->target != last_eye[i] || g->target_part != last_part[i]) stats.eye_shifts++;
            if (g->head_target != last_head[i]) stats.head_shifts++;
            last_eye[i] = g->target;
            last_part[i] = g->target_part;
            last_head[i] = g->head_target;
            if (g->target == CG_NO_TARGET) {
                stats.ahead++;
            } else if (is_character(ids, g->target)) {
                stats.on_characters++;
            } else {
                stats.on_objects++;
            }
            /* The eyes' local rotations are relative to the head (rest: identity). */
            stats.eccentricity += 0.5 * (rotation_degrees(joints[i * JOINTS + 8]) +
                                         rotation_degrees(joints[i * JOINTS + 9]));
            stats.samples++;
        }
    }
    cg_crowd_destroy(crowd);
    return stats;
}

int main(void) {
    static const struct { uint32_t model; const char *name; } models[] = {
        {CG_ATTENTION_MODEL_CROWD, "crowd"},
        {CG_ATTENTION_MODEL_SALIENCY, "saliency"},
        {CG_ATTENTION_MODEL_BASELINE, "baseline"},
    };
    model_stats stats[3];
    int m, failures = 0;
    const double minutes = seconds() / 60.0;

    printf("model     eye shifts/min  head shifts/min  characters  objects  ahead  "
           "eye-in-head  eye fixation\n");
    for (m = 0; m < 3; m++) {
        model_stats *s = &stats[m];
        stats[m] = run(models[m].model);
        printf("%-9s %14.1f  %15.1f  %9.0f%%  %6.0f%%  %4.0f%%  %9.1f deg  %9.2f s\n",
               models[m].name, s->eye_shifts / CHARACTERS / minutes,
               s->head_shifts / CHARACTERS / minutes, 100.0 * s->on_characters / s->samples,
               100.0 * s->on_objects / s->samples, 100.0 * s->ahead / s->samples,
               s->eccentricity / s->samples,
               s->eye_shifts > 0 ? (s->samples / FPS) / s->eye_shifts : 0.0);
    }
    /* What must hold: the baseline never looks at objects; the saliency model shifts the
     * eyes far more often than the crowd model (fixations of at most 0.3 s). */
    if (stats[2].on_objects != 0.0) {
        fprintf(stderr, "the baseline looked at an object\n");
        failures++;
    }
    if (stats[1].eye_shifts < 2.0 * stats[0].eye_shifts) {
        fprintf(stderr, "the saliency model should shift the eyes more often\n");
        failures++;
    }
    if (stats[1].ahead >= stats[0].ahead) {
        fprintf(stderr, "the saliency model should look ahead less than the crowd model\n");
        failures++;
    }
    if (failures) return 1;
    printf("ok\n");
    return 0;
}
