/* street.c: the second example of Grillon & Thalmann 2009 — 130 characters walking up and
 * down a street, standing, or sitting on benches, with 60 scene objects and d_m = 10 m —
 * generated deterministically (street_scene.h) and run for 60 s at 30 fps. Prints each
 * character's attentive fraction (against its attention percentage a) and interest-point
 * count, and the mean cost per character-frame of attention and gaze IK. */
#include <math.h>
#include <time.h>

#include "street_scene.h"

#define CHARACTERS 130
#define OBJECTS 60
#define FPS 30
#define SECONDS 60

int main(void) {
    static street_person people[CHARACTERS];
    static cg_entity_state states[CHARACTERS];
    static uint32_t ids[CHARACTERS];
    static cg_gaze_info gaze[CHARACTERS];
    static float attention_fraction[CHARACTERS];
    street_scene scene;
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    int i, frame, standing = 0, sitting = 0;
    size_t written = 0;
    double seconds_in_step = 0.0, mean_error = 0.0;
    float min_fraction = 1.0f, max_fraction = 0.0f;
    uint32_t total_interests = 0;

    config.struct_size = sizeof config;
    street_check(cg_crowd_config_init(&config), "cg_crowd_config_init");
    config.seed = 130;
    config.max_characters = CHARACTERS;
    config.max_objects = OBJECTS;
    config.max_distance = 10.0f; /* d_m */
    street_check(cg_crowd_create(&config, &crowd), "cg_crowd_create");
    scene.people = people;
    scene.states = states;
    scene.ids = ids;
    street_populate(&scene, crowd, CHARACTERS, OBJECTS, CG_ATTENTION_MODEL_CROWD);
    for (i = 0; i < CHARACTERS; i++) {
        cg_character_params params;
        params.struct_size = sizeof params;
        street_check(cg_crowd_get_character_params(crowd, ids[i], &params), "get params");
        attention_fraction[i] = params.attention_fraction;
        standing += !people[i].walking && !people[i].sitting;
        sitting += people[i].sitting;
    }

    for (frame = 1; frame <= FPS * SECONDS; frame++) {
        const float dt = 1.0f / FPS;
        clock_t start;
        street_advance(&scene, crowd, frame * (double)dt, dt);
        start = clock();
        street_check(cg_crowd_step(crowd, dt), "cg_crowd_step");
        seconds_in_step += (double)(clock() - start) / CLOCKS_PER_SEC;
    }

    street_check(cg_crowd_read_gaze(crowd, gaze, CHARACTERS, &written), "cg_crowd_read_gaze");
    if (written != CHARACTERS) {
        fprintf(stderr, "read %zu gaze records\n", written);
        return 1;
    }
    printf("street: %d characters (%d standing, %d sitting), %d objects, %d s at %d fps\n",
           CHARACTERS, standing, sitting, OBJECTS, SECONDS, FPS);
    printf("character   a     attentive  interest points\n");
    for (i = 0; i < CHARACTERS; i++) {
        float fraction = gaze[i].attentive_fraction;
        if (gaze[i].character != ids[i]) {
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
    printf("interest points: %u in all, %.1f per character per minute\n",
           (unsigned)total_interests, total_interests / (double)CHARACTERS / (SECONDS / 60.0));
    printf("attention + gaze IK step: %.2f us per character-frame (this build)\n",
           1e6 * seconds_in_step / ((double)CHARACTERS * FPS * SECONDS));
    cg_crowd_destroy(crowd);
    if (mean_error > 0.15 || total_interests < CHARACTERS) {
        fprintf(stderr, "implausible attention statistics\n");
        return 1;
    }
    printf("ok\n");
    return 0;
}
