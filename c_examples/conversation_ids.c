/* conversation_ids.c: conversation ids stay unique over many reuses, at capacities where
 * ids made of slot + capacity x generation went wrong. A crowd holds some groups for good
 * while one more pair forms and ends its group again and again; every id it gets must be
 * new, never CG_NO_TARGET, never a held group's; removing a stale id must say
 * CG_STATUS_NOT_FOUND and leave the held groups alone.
 *   - max_conversations 1 048 575: slot 4095 reused 4096 times gave CG_NO_TARGET, so its
 *     members read as in no group;
 *   - 8 372 256 (x 513 = 2^32 + 32): slot 0 reused 513 times gave the id of the held group
 *     in slot 32, and removing it ended that group;
 *   - 8 388 608 (the largest): a slot reused 512 times gave its first id again. */
#include <stdio.h>
#include <stdlib.h>

#include "crowdgaze.h"

/* Stops the program, saying what failed where (and the library's last error). */
static void fail(const char *what, uint32_t capacity, int cycle) {
    char message[256] = "";
    cg_last_error_message(message, sizeof message);
    fprintf(stderr, "max_conversations %u, cycle %d: %s failed (last error: %s)\n",
            (unsigned)capacity, cycle, what, message);
    exit(1);
}

#define REQUIRE(cond) ((cond) ? (void)0 : fail(#cond, capacity, cycle))
#define OK(call) REQUIRE((call) == CG_STATUS_OK)

/* Forms `formed` pairs' groups, removes the first `released` (so that their slots come
 * next), then forms and removes one more pair's group `cycles` times. */
static void reuse(uint32_t capacity, int formed, int released, int cycles) {
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    int characters = 2 * (formed + 1), i, cycle = -1;
    uint32_t *ids = malloc(sizeof *ids * (size_t)characters);
    uint32_t *groups = malloc(sizeof *groups * (size_t)formed);
    uint32_t *pair, group = CG_NO_TARGET, previous = 0, found;
    REQUIRE(ids && groups);
    config.struct_size = sizeof config;
    OK(cg_crowd_config_init(&config));
    config.max_characters = (uint32_t)characters;
    config.max_conversations = capacity;
    OK(cg_crowd_create(&config, &crowd));
    for (i = 0; i < characters; i++) {
        cg_character_desc desc;
        desc.struct_size = sizeof desc;
        OK(cg_character_desc_init(&desc));
        desc.position.x = (float)i;
        OK(cg_crowd_add_character(crowd, &desc, &ids[i]));
    }
    for (i = 0; i < formed; i++) {
        OK(cg_crowd_set_conversation(crowd, &ids[2 * i], 2, &groups[i]));
    }
    for (i = 0; i < released; i++) {
        OK(cg_crowd_remove_conversation(crowd, groups[i]));
    }
    pair = &ids[2 * formed];
    for (cycle = 0; cycle < cycles; cycle++) {
        OK(cg_crowd_set_conversation(crowd, pair, 2, &group));
        REQUIRE(group != CG_NO_TARGET);
        /* Given in turn: never one given before, so never a held group's. */
        REQUIRE(cycle == 0 || group > previous);
        for (i = released; i < formed; i++) {
            REQUIRE(group != groups[i]);
        }
        previous = group;
        OK(cg_crowd_get_conversation(crowd, pair[0], &found));
        REQUIRE(found == group);
        OK(cg_crowd_remove_conversation(crowd, group));
        REQUIRE(cg_crowd_remove_conversation(crowd, group) == CG_STATUS_NOT_FOUND);
    }
    for (i = released; i < formed; i++) {
        OK(cg_crowd_get_conversation(crowd, ids[2 * i + 1], &found));
        REQUIRE(found == groups[i]);
    }
    printf("max_conversations %u: %d reuses, the last id %u\n", (unsigned)capacity, cycles,
           (unsigned)group);
    cg_crowd_destroy(crowd);
    free(ids);
    free(groups);
}

int main(void) {
    reuse(1048575u, 4097, 4096, 4200);
    reuse(8372256u, 33, 1, 600);
    reuse(8388608u, 1, 0, 600);
    printf("ok\n");
    return 0;
}
