/* chain.c: describes a gaze chain from C — the human default for a Z-up skeleton facing
 * -Y, scaled to centimetres, and the errors of cg_chain_desc_init_human. */
#include <stdio.h>
#include <string.h>

#include "crowdgaze.h"

static int failures = 0;

#define CHECK(cond)                                                         \
    do {                                                                    \
        if (!(cond)) {                                                      \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            failures++;                                                     \
        }                                                                   \
    } while (0)

int main(void) {
    cg_chain_desc desc;
    uint32_t i;
    float eye_height;
    desc.struct_size = sizeof desc;
    CHECK(cg_chain_desc_init_human(&desc, CG_AXIS_POSITIVE_Z, CG_AXIS_NEGATIVE_Y) == CG_STATUS_OK);
    CHECK(desc.struct_size == sizeof desc);
    CHECK(desc.joint_count == 10);
    CHECK(desc.joints[0].role == CG_JOINT_ROLE_SPINE);
    CHECK(desc.joints[7].role == CG_JOINT_ROLE_HEAD);
    CHECK(desc.joints[8].role == CG_JOINT_ROLE_LEFT_EYE);
    CHECK(desc.joints[9].role == CG_JOINT_ROLE_RIGHT_EYE);
    CHECK(desc.eye_forward.y == -1.0f && desc.eye_up.z == 1.0f);
    /* The left eye is on the character's left: up x forward = Z x -Y = +X. */
    CHECK(desc.joints[8].offset.x > 0.0f && desc.joints[9].offset.x < 0.0f);

    /* Rest rotations are identity: the eye height is the sum of the offsets along up. */
    eye_height = desc.root_offset.z;
    for (i = 0; i < 8; i++) {
        eye_height += desc.joints[i].offset.z;
    }
    eye_height += desc.joints[8].offset.z;
    printf("joints %u, eye height %.2f m\n", (unsigned)desc.joint_count, eye_height);
    CHECK(eye_height > 1.55f && eye_height < 1.70f);

    /* Unreal-style centimetres: scale the lengths by units_per_metre. */
    for (i = 0; i < desc.joint_count; i++) {
        desc.joints[i].offset.x *= 100.0f;
        desc.joints[i].offset.y *= 100.0f;
        desc.joints[i].offset.z *= 100.0f;
    }
    desc.root_offset.z *= 100.0f;
    printf("pelvis at %.0f cm\n", desc.root_offset.z);

    {
        cg_chain_desc untouched;
        memcpy(&untouched, &desc, sizeof desc);
        CHECK(cg_chain_desc_init_human(NULL, CG_AXIS_POSITIVE_Y, CG_AXIS_POSITIVE_Z) ==
              CG_STATUS_NULL_ARGUMENT);
        CHECK(cg_chain_desc_init_human(&desc, CG_AXIS_POSITIVE_Y, CG_AXIS_NEGATIVE_Y) ==
              CG_STATUS_INVALID_ARGUMENT);
        CHECK(cg_chain_desc_init_human(&desc, 42u, CG_AXIS_POSITIVE_Z) ==
              CG_STATUS_INVALID_ARGUMENT);
        CHECK(memcmp(&untouched, &desc, sizeof desc) == 0);
    }

    if (failures != 0) {
        return 1;
    }
    printf("ok\n");
    return 0;
}
