// header_twice.cpp: the header compiles as C++17 (inside extern "C"), may be included
// twice, and its types and functions are usable from C++.
#include "crowdgaze.h"
#include "crowdgaze.h"

#include <cstdio>
#include <memory>

int main() {
    cg_crowd_config config;
    config.struct_size = sizeof config;
    if (cg_crowd_config_init(&config) != CG_STATUS_OK) return 1;
    cg_crowd* raw = nullptr;
    if (cg_crowd_create(&config, &raw) != CG_STATUS_OK) return 1;
    std::unique_ptr<cg_crowd, decltype(&cg_crowd_destroy)> crowd(raw, &cg_crowd_destroy);
    cg_quat identity{0.0f, 0.0f, 0.0f, 1.0f};
    cg_dualquat pose{identity, {0.0f, 0.0f, 0.0f, 0.0f}};
    cg_vec3 position{1.0f, 2.0f, 3.0f};
    std::printf("C++ sees crowdgaze %s; quaternion w %.1f, position x %.1f, pose real w %.1f\n",
                cg_version_string(), identity.w, position.x, pose.real.w);
    std::printf("ok\n");
    return 0;
}
