/* main.c: a program built against an installed crowdgaze (CMake package or pkg-config).
 * Two characters face each other 3 m apart; after a second each looks at the other.
 * Prints the library version, who looks at whom and the eye direction, then "ok". */
#include <math.h>
#include <stdio.h>

#include "crowdgaze.h"

static int check(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[256];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s: %s\n", what, message);
        return 0;
    }
    return 1;
}

int main(void) {
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    cg_character_desc desc;
    cg_gaze_target target;
    cg_eye_info eyes[2];
    uint32_t ids[2];
    int i, good = 1;
    float dz;

    if (cg_version() >> 16 != CG_VERSION_MAJOR) {
        fprintf(stderr, "header %d.x, library %s\n", CG_VERSION_MAJOR, cg_version_string());
        return 1;
    }
    printf("crowdgaze %s\n", cg_version_string());
    config.struct_size = sizeof config;
    good &= check(cg_crowd_config_init(&config), "config");
    config.max_characters = 2;
    good &= check(cg_crowd_create(&config, &crowd), "create");
    if (!good) return 1;
    for (i = 0; i < 2; i++) {
        desc.struct_size = sizeof desc;
        cg_character_desc_init(&desc);
        desc.position.z = 3.0f * (float)i;
        desc.heading = i == 0 ? 0.0f : 3.14159265f;
        good &= check(cg_crowd_add_character(crowd, &desc, &ids[i]), "add");
    }
    /* Each looks at the other (an entity target followed as it moves). */
    for (i = 0; i < 2; i++) {
        target.struct_size = sizeof target;
        cg_gaze_target_init(&target);
        target.kind = CG_GAZE_TARGET_ENTITY;
        target.entity = ids[1 - i];
        good &= check(cg_crowd_set_gaze_target(crowd, ids[i], &target), "target");
    }
    for (i = 0; i < 30; i++) good &= check(cg_crowd_step(crowd, 1.0f / 30.0f), "step");
    good &= check(cg_crowd_read_eyes(crowd, 0, 2, eyes, 2), "eyes");
    /* Character 0 looks along +z towards character 1, character 1 along -z. */
    dz = eyes[0].left_direction.z;
    printf("character %u looks at %u: eye direction (%.2f, %.2f, %.2f)\n", ids[0], ids[1],
           (double)eyes[0].left_direction.x, (double)eyes[0].left_direction.y, (double)dz);
    good &= dz > 0.99f && eyes[1].left_direction.z < -0.99f;
    cg_crowd_destroy(crowd);
    if (!good) {
        fprintf(stderr, "checks failed\n");
        return 1;
    }
    printf("ok\n");
    return 0;
}
