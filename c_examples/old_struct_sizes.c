/* old_struct_sizes.c: the library reads and writes no more of a versioned struct than its
 * struct_size says. Each struct lives in a heap block of exactly its size followed by guard
 * bytes: every call that fills, reads or returns the struct must leave the guard intact.
 * cg_crowd_config is also passed in its four older layouts, of 144 bytes (everything
 * before reorder_period), 152 bytes (everything before the blink fields, padded), 176 bytes
 * (everything before the conversation fields, padded) and 216 bytes (everything before the
 * street and following fields), as programs built against older headers have it. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "crowdgaze.h"

#define GUARD_BYTES 64
#define GUARD 0xA5

/* The sizes of cg_crowd_config before reorder_period, before blink_rate and before
 * max_conversations were added (C pads the struct to 8 bytes, for its uint64_t seed). */
#define CROWD_CONFIG_SIZE_BEFORE_REORDER offsetof(cg_crowd_config, reorder_period)
#define CROWD_CONFIG_SIZE_BEFORE_BLINKS ((offsetof(cg_crowd_config, blink_rate) + 7) / 8 * 8)
#define CROWD_CONFIG_SIZE_BEFORE_CONVERSATIONS                                           \
    ((offsetof(cg_crowd_config, max_conversations) + 7) / 8 * 8)
#define CROWD_CONFIG_SIZE_BEFORE_STREET                                                  \
    ((offsetof(cg_crowd_config, street_view_half_angle) + 7) / 8 * 8)

static int failures = 0;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);    \
            failures++;                                                                  \
        }                                                                                \
    } while (0)

/* A block of `size` bytes followed by GUARD_BYTES guard bytes; the struct's first field,
 * struct_size, is set to `size`. */
static void *guarded(size_t size) {
    unsigned char *block = malloc(size + GUARD_BYTES);
    if (block == NULL) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    memset(block, 0, size);
    memset(block + size, GUARD, GUARD_BYTES);
    *(uint32_t *)(void *)block = (uint32_t)size;
    return block;
}

/* Whether the guard after a block of `size` bytes is intact. */
static int guard_intact(const void *block, size_t size) {
    const unsigned char *guard = (const unsigned char *)block + size;
    size_t i;
    for (i = 0; i < GUARD_BYTES; i++) {
        if (guard[i] != GUARD) {
            return 0;
        }
    }
    return 1;
}

#define CHECK_GUARD(block, size, what)                                                   \
    do {                                                                                 \
        int intact_ = guard_intact((block), (size));                                     \
        CHECK(intact_);                                                                  \
        printf("%s (%u bytes): guard %s\n", (what), (unsigned)(size),                   \
               intact_ ? "intact" : "OVERWRITTEN");                                      \
    } while (0)

/* An older cg_crowd_config of `size` bytes: init, create, get, each within its size. */
static void old_crowd_config(size_t size) {
    cg_crowd_config *config = guarded(size);
    cg_crowd *crowd = NULL;

    CHECK(size < sizeof(cg_crowd_config));
    CHECK(cg_crowd_config_init(config) == CG_STATUS_OK);
    CHECK_GUARD(config, size, "older cg_crowd_config, cg_crowd_config_init");
    CHECK(config->struct_size == size);
    CHECK(config->max_characters == 1024 && config->threads == 1);

    config->max_characters = 8;
    config->threads = 2;
    CHECK(cg_crowd_create(config, &crowd) == CG_STATUS_OK);
    CHECK_GUARD(config, size, "older cg_crowd_config, cg_crowd_create");

    memset(config, 0, size);
    config->struct_size = (uint32_t)size;
    CHECK(cg_crowd_get_config(crowd, config) == CG_STATUS_OK);
    CHECK_GUARD(config, size, "older cg_crowd_config, cg_crowd_get_config");
    CHECK(config->struct_size == size);
    CHECK(config->max_characters == 8 && config->threads == 2);

    /* The fields the older layout lacks take their defaults. */
    {
        cg_crowd_config current;
        memset(&current, 0xff, sizeof current);
        current.struct_size = sizeof current;
        CHECK(cg_crowd_get_config(crowd, &current) == CG_STATUS_OK);
        CHECK(current.threads == 2 && current.reorder_period == 0); /* its default */
        CHECK(current.blink_rate == 17.0f && current.lid_gain == 1.0f);
        CHECK(current.eye_motion == CG_EYE_MOTION_PAPER);
        CHECK(current.max_conversations == 64 && current.talking_gain == 1.5f);
        CHECK(current.eye_part_weight == 1.5f);
        CHECK(current.listener_look_share == 0.75f && current.listener_glance_time == 6.0f);
        CHECK(current.speaker_look_share == 0.41f && current.speaker_glance_time == 1.8f);
        CHECK(current.idle_look_share == 0.5f && current.idle_glance_time == 2.5f);
        CHECK(current.turn_start_aversion_time == 1.0f);
        CHECK(current.street_first_fixation_probability == 0.95f);
        CHECK(current.street_civil_distance == 3.0f && current.street_refixation_gap_max == 2.0f);
        CHECK(current.street_miss_after == 1.0f && current.follow_reaction_max == 1.0f);
        CHECK(current.follow_enabled == 0 && current.follow_distance == 10.0f);
        CHECK(current.follow_one_looker_probability == 0.42f);
        CHECK(current.follow_forget_time == 10.0f);
    }

    /* A struct_size that is no layout's: refused, nothing written. */
    config->struct_size = 0;
    config->max_characters = 3;
    CHECK(cg_crowd_config_init(config) == CG_STATUS_BAD_STRUCT_SIZE);
    CHECK(cg_crowd_get_config(crowd, config) == CG_STATUS_BAD_STRUCT_SIZE);
    CHECK(config->struct_size == 0 && config->max_characters == 3);
    config->struct_size = (uint32_t)size + 4;
    CHECK(cg_crowd_config_init(config) == CG_STATUS_BAD_STRUCT_SIZE);
    CHECK(config->max_characters == 3);
    CHECK_GUARD(config, size, "older cg_crowd_config, refused sizes");

    cg_crowd_destroy(crowd);
    free(config);
}

/* Every versioned struct at its current size, in a block of exactly that size. */
static void current_sizes(void) {
    cg_crowd_config *config = guarded(sizeof *config);
    cg_character_desc *character = guarded(sizeof *character);
    cg_object_desc *object = guarded(sizeof *object);
    cg_entity_state *state = guarded(sizeof *state);
    cg_gaze_target *target = guarded(sizeof *target);
    cg_chain_desc *chain = guarded(sizeof *chain);
    cg_character_params *params = guarded(sizeof *params);
    cg_view_blender_config *blender_config = guarded(sizeof *blender_config);
    cg_crowd *crowd = NULL;
    cg_view_blender *blender = NULL;
    uint32_t person = 0, thing = 0;

    CHECK(cg_crowd_config_init(config) == CG_STATUS_OK);
    config->max_characters = 4;
    CHECK(cg_crowd_create(config, &crowd) == CG_STATUS_OK);
    config->struct_size = sizeof *config;
    CHECK(cg_crowd_get_config(crowd, config) == CG_STATUS_OK);
    CHECK_GUARD(config, sizeof *config, "cg_crowd_config");

    CHECK(cg_chain_desc_init_human(chain, CG_AXIS_POSITIVE_Y, CG_AXIS_POSITIVE_Z) ==
          CG_STATUS_OK);
    CHECK_GUARD(chain, sizeof *chain, "cg_chain_desc");

    CHECK(cg_character_desc_init(character) == CG_STATUS_OK);
    character->chain = chain;
    CHECK(cg_crowd_add_character(crowd, character, &person) == CG_STATUS_OK);
    CHECK_GUARD(character, sizeof *character, "cg_character_desc");

    CHECK(cg_object_desc_init(object) == CG_STATUS_OK);
    object->position.z = 2.0f;
    CHECK(cg_crowd_add_object(crowd, object, &thing) == CG_STATUS_OK);
    CHECK_GUARD(object, sizeof *object, "cg_object_desc");

    CHECK(cg_entity_state_init(state) == CG_STATUS_OK);
    state->id = person;
    CHECK(cg_crowd_push_frame(crowd, 0.0, state, 1) == CG_STATUS_OK);
    CHECK_GUARD(state, sizeof *state, "cg_entity_state");

    CHECK(cg_gaze_target_init(target) == CG_STATUS_OK);
    target->kind = CG_GAZE_TARGET_ENTITY;
    target->entity = thing;
    CHECK(cg_crowd_set_gaze_target(crowd, person, target) == CG_STATUS_OK);
    CHECK_GUARD(target, sizeof *target, "cg_gaze_target");

    CHECK(cg_crowd_get_character_params(crowd, person, params) == CG_STATUS_OK);
    CHECK(cg_crowd_set_character_params(crowd, person, params) == CG_STATUS_OK);
    CHECK_GUARD(params, sizeof *params, "cg_character_params");

    CHECK(cg_view_blender_config_init(blender_config) == CG_STATUS_OK);
    blender_config->joint_count = 2;
    blender_config->key_count = 1;
    CHECK(cg_view_blender_create(blender_config, &blender) == CG_STATUS_OK);
    CHECK_GUARD(blender_config, sizeof *blender_config, "cg_view_blender_config");

    cg_view_blender_destroy(blender);
    cg_crowd_destroy(crowd);
    free(config);
    free(character);
    free(object);
    free(state);
    free(target);
    free(chain);
    free(params);
    free(blender_config);
}

int main(void) {
    CHECK(CROWD_CONFIG_SIZE_BEFORE_REORDER == 144 && CROWD_CONFIG_SIZE_BEFORE_BLINKS == 152);
    CHECK(CROWD_CONFIG_SIZE_BEFORE_CONVERSATIONS == 176 && CROWD_CONFIG_SIZE_BEFORE_STREET == 216);
    CHECK(sizeof(cg_crowd_config) == 320);
    old_crowd_config(CROWD_CONFIG_SIZE_BEFORE_REORDER);
    old_crowd_config(CROWD_CONFIG_SIZE_BEFORE_BLINKS);
    old_crowd_config(CROWD_CONFIG_SIZE_BEFORE_CONVERSATIONS);
    old_crowd_config(CROWD_CONFIG_SIZE_BEFORE_STREET);
    current_sizes();
    if (failures != 0) {
        return 1;
    }
    printf("ok\n");
    return 0;
}
