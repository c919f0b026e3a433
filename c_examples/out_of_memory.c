/* out_of_memory.c: capacities at their documented maxima never kill the caller. Each create
 * (and the calls that size buffers from the caller's numbers: a key clip, a plan) either
 * succeeds or returns CG_STATUS_OUT_OF_MEMORY, writes no handle, and names the field and the
 * bytes asked in cg_last_error_message.
 *
 * Each case runs in a child process whose address space is capped at 2 GiB with
 * setrlimit(RLIMIT_AS), as on consoles and in containers; the child exits with the status it
 * got, and the parent checks that it exited normally (not by a signal: an allocation failure
 * inside Rust aborts with SIGABRT) with the expected status.
 *
 * Under scripts/memcheck (valgrind, or AddressSanitizer: both reserve far more address space
 * than the cap) the capped children are skipped; the uncapped case, a recording of
 * 4 294 967 295 states (275 GB, refused by the allocator unless memory is overcommitted),
 * still runs the failure path in this process, where the checkers see any leak of a
 * half-built crowd. */
#define _XOPEN_SOURCE 700

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "crowdgaze.h"

#if defined(__SANITIZE_ADDRESS__)
#define CG_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CG_ASAN 1
#endif
#endif

#ifdef CG_ASAN
/* AddressSanitizer aborts on a failed allocation unless told to return NULL, as malloc does. */
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "allocator_may_return_null=1"; }
#endif

/* The address space of each capped child. */
#define CAP ((rlim_t)2 << 30)
/* Exit codes of a child that failed before or after its call (statuses are below 64). */
#define SETUP_FAILED 100
#define BAD_MESSAGE 101
#define HANDLE_WRITTEN 102
#define NO_CAP 103

static int failures = 0;

/* Checks that the last error is an out-of-memory message naming `field` and a byte count. */
static int names_field_and_bytes(const char *field) {
    char message[512];
    cg_last_error_message(message, sizeof message);
    printf("  %s\n", message);
    return strncmp(message, "out of memory: ", 15) == 0 && strstr(message, field) != NULL &&
           strstr(message, " bytes") != NULL;
}

/* A crowd config with the given capacities, other fields at their defaults. */
static cg_crowd_config crowd_config(uint32_t characters, uint32_t objects, uint32_t states) {
    cg_crowd_config config;
    config.struct_size = sizeof config;
    cg_crowd_config_init(&config);
    config.max_characters = characters;
    config.max_objects = objects;
    config.max_recorded_states = states;
    return config;
}

/* cg_crowd_create at the given capacities: its status; on failure the message must name
 * `field` and no handle may be written. */
static int create_crowd(uint32_t characters, uint32_t objects, uint32_t states,
                        const char *field) {
    cg_crowd_config config = crowd_config(characters, objects, states);
    cg_crowd *crowd = NULL;
    cg_status status = cg_crowd_create(&config, &crowd);
    if (status == CG_STATUS_OK) {
        cg_crowd_destroy(crowd);
        return status;
    }
    if (crowd != NULL) return HANDLE_WRITTEN;
    if (status == CG_STATUS_OUT_OF_MEMORY && !names_field_and_bytes(field)) return BAD_MESSAGE;
    return (int)status;
}

static int most_characters(void) { return create_crowd(16777216u, 256, 0, "max_characters"); }
static int most_objects(void) { return create_crowd(1, 16777216u, 0, "max_objects"); }
static int most_states(void) { return create_crowd(1024, 256, UINT32_MAX, "max_recorded_states"); }
static int most_of_all(void) { return create_crowd(16777216u, 16777216u, UINT32_MAX, "max_"); }

/* The largest view blender (it fits), its largest static pose (fits), then a clip whose copy
 * does not fit beside the caller's own frames. */
static int largest_blender(void) {
    cg_view_blender_config config;
    cg_view_blender *blender = NULL;
    cg_dualquat *frames;
    size_t joints = 65536, frame_count = 560, i, count = joints * frame_count;
    cg_status status;
    config.struct_size = sizeof config;
    cg_view_blender_config_init(&config);
    config.joint_count = (uint32_t)joints;
    config.key_count = 32;
    status = cg_view_blender_create(&config, &blender);
    if (status != CG_STATUS_OK) return SETUP_FAILED;
    /* 560 frames of 65536 joints: 1.1 GiB here, as much again for the library's copy. */
    frames = malloc(count * sizeof *frames);
    if (frames == NULL) return SETUP_FAILED;
    for (i = 0; i < count; i++) {
        memset(&frames[i], 0, sizeof frames[i]);
        frames[i].real.w = 1.0f;
    }
    if (cg_view_blender_set_key_pose(blender, 31, frames, joints) != CG_STATUS_OK) {
        return SETUP_FAILED;
    }
    status = cg_view_blender_set_key_clip(blender, 0, frames, frame_count, 30.0f, true);
    if (status == CG_STATUS_OUT_OF_MEMORY && !names_field_and_bytes("a clip of 560 frames")) {
        status = BAD_MESSAGE;
    }
    free(frames);
    cg_view_blender_destroy(blender);
    return (int)status;
}

/* A plan of 40 000 recorded frames of 4096 characters: 2.6 GB of scores. */
static int largest_plan(void) {
    cg_crowd_config config = crowd_config(4096, 0, 40000);
    cg_crowd *crowd = NULL;
    cg_character_desc desc;
    uint32_t id, c, frame;
    cg_status status;
    if (cg_crowd_create(&config, &crowd) != CG_STATUS_OK) return SETUP_FAILED;
    desc.struct_size = sizeof desc;
    cg_character_desc_init(&desc);
    for (c = 0; c < 4096; c++) {
        desc.position.x = (float)(c % 64);
        desc.position.z = (float)(c / 64);
        if (cg_crowd_add_character(crowd, &desc, &id) != CG_STATUS_OK) return SETUP_FAILED;
    }
    for (frame = 0; frame < 40000; frame++) {
        if (cg_crowd_push_frame(crowd, frame / 30.0, NULL, 0) != CG_STATUS_OK) {
            return SETUP_FAILED;
        }
    }
    status = cg_crowd_plan(crowd);
    if (status == CG_STATUS_OUT_OF_MEMORY && !names_field_and_bytes("40000 recorded frames")) {
        status = BAD_MESSAGE;
    }
    /* Nothing changed: the crowd is still online and steps. */
    if (status == CG_STATUS_OUT_OF_MEMORY && cg_crowd_step(crowd, 1.0f / 30.0f) != CG_STATUS_OK) {
        status = SETUP_FAILED;
    }
    cg_crowd_destroy(crowd);
    return (int)status;
}

/* Either status: a maximum at the edge of the cap. */
#define OK_OR_OUT_OF_MEMORY (-1)

/* Runs `run` in a child capped at CAP bytes of address space; checks it exits with
 * `expected` (a status, or OK_OR_OUT_OF_MEMORY). */
static void capped(const char *what, int (*run)(void), int expected) {
    int code;
    pid_t child;
    int wait_status = 0;
    fflush(stdout);
    child = fork();
    if (child < 0) {
        perror("fork");
        failures++;
        return;
    }
    if (child == 0) {
        struct rlimit limit;
        limit.rlim_cur = CAP;
        limit.rlim_max = CAP;
        if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(NO_CAP);
        printf("%s (address space capped at 2 GiB):\n", what);
        fflush(stdout);
        {
            int code = run();
            fflush(stdout);
            _exit(code);
        }
    }
    if (waitpid(child, &wait_status, 0) != child) {
        perror("waitpid");
        failures++;
    } else if (WIFSIGNALED(wait_status)) {
        printf("  FAILED: killed by signal %d\n", WTERMSIG(wait_status));
        failures++;
    } else if (!WIFEXITED(wait_status)) {
        printf("  FAILED: the child neither exited nor was killed\n");
        failures++;
    } else {
        code = WEXITSTATUS(wait_status);
        if (code == expected || (expected == OK_OR_OUT_OF_MEMORY &&
                                  (code == CG_STATUS_OK || code == CG_STATUS_OUT_OF_MEMORY))) {
            printf("  -> %s\n", cg_status_str((uint32_t)code));
        } else {
            printf("  FAILED: exit code %d, expected %d\n", code, expected);
            failures++;
        }
    }
}

/* True under scripts/memcheck: valgrind runs the example, or sanitizers are compiled in. */
static int under_memory_checker(void) {
    const char *runner = getenv("CG_EXAMPLE_RUNNER");
    const char *flags = getenv("CG_EXAMPLE_CFLAGS");
#ifdef CG_ASAN
    return 1;
#endif
    return (runner != NULL && runner[0] != '\0') || (flags != NULL && flags[0] != '\0');
}

int main(void) {
    int status;
    if (under_memory_checker()) {
        printf("under a memory checker: the children capped at 2 GiB are skipped\n");
    } else {
        capped("max_characters = 16777216", most_characters, CG_STATUS_OUT_OF_MEMORY);
        /* About 130 bytes per object: 2.2 GB, at the edge of the cap. */
        capped("max_objects = 16777216", most_objects, OK_OR_OUT_OF_MEMORY);
        capped("max_recorded_states = 4294967295", most_states, CG_STATUS_OUT_OF_MEMORY);
        capped("every capacity at its maximum", most_of_all, CG_STATUS_OUT_OF_MEMORY);
        capped("a clip of 560 frames x 65536 joints", largest_blender, CG_STATUS_OUT_OF_MEMORY);
        capped("a plan of 40000 frames x 4096 characters", largest_plan,
               CG_STATUS_OUT_OF_MEMORY);
    }

    /* Uncapped, in this process: 275 GB of recording is refused by the allocator (or, where
     * memory is overcommitted, reserved and never touched). */
    printf("max_recorded_states = 4294967295 (uncapped):\n");
    status = most_states();
    if (status == CG_STATUS_OK || status == CG_STATUS_OUT_OF_MEMORY) {
        printf("  -> %s\n", cg_status_str((uint32_t)status));
    } else {
        printf("  FAILED: %d\n", status);
        failures++;
    }

    if (failures != 0) {
        printf("%d failure(s)\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
