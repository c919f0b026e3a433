/* errors.c: the error conventions seen from C — every status string, NULL arguments,
 * a bad or unset struct_size, a bad field, and cg_last_error_message with small and NULL
 * buffers. */
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

static void print_last_error(const char *what) {
    char message[256];
    size_t length = cg_last_error_message(message, sizeof message);
    printf("%s -> %s (%zu bytes)\n", what, message, length);
}

int main(void) {
    static const struct { cg_status status; const char *name; } statuses[] = {
        {CG_STATUS_OK, "CG_STATUS_OK"},
        {CG_STATUS_NULL_ARGUMENT, "CG_STATUS_NULL_ARGUMENT"},
        {CG_STATUS_INVALID_ARGUMENT, "CG_STATUS_INVALID_ARGUMENT"},
        {CG_STATUS_NON_FINITE, "CG_STATUS_NON_FINITE"},
        {CG_STATUS_NOT_FOUND, "CG_STATUS_NOT_FOUND"},
        {CG_STATUS_CAPACITY, "CG_STATUS_CAPACITY"},
        {CG_STATUS_BAD_STRUCT_SIZE, "CG_STATUS_BAD_STRUCT_SIZE"},
        {CG_STATUS_WRONG_STATE, "CG_STATUS_WRONG_STATE"},
        {CG_STATUS_NOT_CONVERGED, "CG_STATUS_NOT_CONVERGED"},
        {CG_STATUS_INTERNAL, "CG_STATUS_INTERNAL"},
        {CG_STATUS_OUT_OF_MEMORY, "CG_STATUS_OUT_OF_MEMORY"},
        {CG_STATUS_POISONED, "CG_STATUS_POISONED"},
    };
    size_t i;
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    char tiny[8];
    size_t length;

    /* Every status has its own string; an unknown value says so. */
    for (i = 0; i < sizeof statuses / sizeof statuses[0]; i++) {
        const char *text = cg_status_str(statuses[i].status);
        CHECK(text != NULL && text[0] != '\0');
        CHECK(statuses[i].status == (cg_status)i);
        printf("%s: %s\n", statuses[i].name, text);
    }
    CHECK(strcmp(cg_status_str(12345u), "unknown status") == 0);

    /* NULL arguments. */
    CHECK(cg_crowd_config_init(NULL) == CG_STATUS_NULL_ARGUMENT);
    print_last_error("cg_crowd_config_init(NULL)");
    config.struct_size = sizeof config;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_OK);
    CHECK(cg_crowd_create(NULL, &crowd) == CG_STATUS_NULL_ARGUMENT);
    CHECK(cg_crowd_create(&config, NULL) == CG_STATUS_NULL_ARGUMENT);
    print_last_error("cg_crowd_create(&config, NULL)");
    CHECK(cg_crowd_get_config(NULL, &config) == CG_STATUS_NULL_ARGUMENT);
    cg_crowd_destroy(NULL); /* accepted and ignored */

    /* A config not filled by cg_crowd_config_init. */
    config.struct_size = 3;
    CHECK(cg_crowd_create(&config, &crowd) == CG_STATUS_BAD_STRUCT_SIZE);
    CHECK(crowd == NULL); /* outputs are written only on success */
    print_last_error("struct_size 3");

    /* An _init call on a struct whose struct_size is not set (0 here) writes nothing. */
    config.struct_size = 0;
    config.seed = 7;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_BAD_STRUCT_SIZE);
    CHECK(config.struct_size == 0 && config.seed == 7);
    print_last_error("cg_crowd_config_init, struct_size 0");

    /* Bad fields. */
    config.struct_size = sizeof config;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_OK);
    config.up_axis = CG_AXIS_POSITIVE_Y;
    config.forward_axis = CG_AXIS_NEGATIVE_Y;
    CHECK(cg_crowd_create(&config, &crowd) == CG_STATUS_INVALID_ARGUMENT);
    print_last_error("up = +Y, forward = -Y");
    config.struct_size = sizeof config;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_OK);
    config.units_per_metre = 0.0f / 0.0f;
    CHECK(cg_crowd_create(&config, &crowd) == CG_STATUS_NON_FINITE);
    print_last_error("units_per_metre NaN");
    config.struct_size = sizeof config;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_OK);
    config.max_characters = 0;
    CHECK(cg_crowd_create(&config, &crowd) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(crowd == NULL);

    /* The message: its full length is returned whatever the buffer. */
    length = cg_last_error_message(NULL, 0);
    CHECK(length > sizeof tiny);
    CHECK(cg_last_error_message(tiny, sizeof tiny) == length);
    CHECK(strlen(tiny) == sizeof tiny - 1);
    printf("truncated message: \"%s\" of %zu bytes\n", tiny, length);

    /* A good crowd, and its config read back. */
    config.struct_size = sizeof config;
    CHECK(cg_crowd_config_init(&config) == CG_STATUS_OK);
    config.seed = 42;
    config.units_per_metre = 100.0f;
    config.up_axis = CG_AXIS_POSITIVE_Z;
    config.forward_axis = CG_AXIS_POSITIVE_X;
    CHECK(cg_crowd_create(&config, &crowd) == CG_STATUS_OK);
    CHECK(crowd != NULL);
    {
        cg_crowd_config back;
        back.struct_size = sizeof back;
        CHECK(cg_crowd_get_config(crowd, &back) == CG_STATUS_OK);
        CHECK(back.seed == 42 && back.units_per_metre == 100.0f);
        CHECK(back.up_axis == CG_AXIS_POSITIVE_Z && back.forward_axis == CG_AXIS_POSITIVE_X);
        CHECK(back.struct_size == sizeof back);
    }
    cg_crowd_destroy(crowd);

    if (failures != 0) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
