/* version.c: checks that the header and the linked library agree on the version. */
#include <stdio.h>
#include <string.h>

#include "crowdgaze.h"

int main(void) {
    uint32_t header = ((uint32_t)CG_VERSION_MAJOR << 16) | ((uint32_t)CG_VERSION_MINOR << 8) |
                      (uint32_t)CG_VERSION_PATCH;
    char expected[32];
    printf("header %d.%d.%d\n", CG_VERSION_MAJOR, CG_VERSION_MINOR, CG_VERSION_PATCH);
    printf("library %s (0x%06x)\n", cg_version_string(), (unsigned)cg_version());
    if (cg_version() != header) {
        fprintf(stderr, "header and library versions differ\n");
        return 1;
    }
    snprintf(expected, sizeof expected, "%d.%d.%d", CG_VERSION_MAJOR, CG_VERSION_MINOR,
             CG_VERSION_PATCH);
    if (strcmp(expected, cg_version_string()) != 0) {
        fprintf(stderr, "version string %s, expected %s\n", cg_version_string(), expected);
        return 1;
    }
    printf("ok\n");
    return 0;
}
