// rig_cpp.cpp: your own skeleton with the C++ wrapper. A Mixamo-style skeleton (Y up, +Z
// forward, centimetres) is mapped to a gaze chain in one call, with no overrides; its
// character joins a crowd in centimetres and looks at a point. Each frame the animation's
// bone rotations become the crowd's base pose, and the crowd's joints are written back as
// bone rotations, which forward kinematics turns into the head's direction.
#include "crowdgaze.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Bone {
    const char* name;
    const char* parent;  // nullptr: none
    cg_vec3 offset;      // from the parent, cm
};

// Names, parents and offsets as a Mixamo FBX has them (the rest rotations are identity).
const Bone kSkeleton[] = {
    {"mixamorig:Hips", nullptr, {0.0f, 98.0f, 0.0f}},
    {"mixamorig:Spine", "mixamorig:Hips", {0.0f, 7.0f, 0.0f}},
    {"mixamorig:Spine1", "mixamorig:Spine", {0.0f, 16.0f, -1.0f}},
    {"mixamorig:Spine2", "mixamorig:Spine1", {0.0f, 16.0f, -1.0f}},
    {"mixamorig:Neck", "mixamorig:Spine2", {0.0f, 9.0f, -1.0f}},
    {"mixamorig:Head", "mixamorig:Neck", {0.0f, 14.0f, 3.0f}},
    {"mixamorig:HeadTop_End", "mixamorig:Head", {0.0f, 18.0f, 0.0f}},
    {"mixamorig:LeftEye", "mixamorig:Head", {3.2f, 8.0f, 9.0f}},
    {"mixamorig:RightEye", "mixamorig:Head", {-3.2f, 8.0f, 9.0f}},
    {"mixamorig:LeftShoulder", "mixamorig:Spine2", {2.5f, 6.0f, 2.0f}},
    {"mixamorig:LeftArm", "mixamorig:LeftShoulder", {14.5f, -1.0f, -3.0f}},
    {"mixamorig:LeftForeArm", "mixamorig:LeftArm", {28.0f, 0.0f, -1.0f}},
    {"mixamorig:RightShoulder", "mixamorig:Spine2", {-2.5f, 6.0f, 2.0f}},
    {"mixamorig:RightArm", "mixamorig:RightShoulder", {-14.5f, -1.0f, -3.0f}},
    {"mixamorig:RightForeArm", "mixamorig:RightArm", {-28.0f, 0.0f, -1.0f}},
    {"mixamorig:LeftUpLeg", "mixamorig:Hips", {9.0f, -5.0f, 0.0f}},
    {"mixamorig:LeftLeg", "mixamorig:LeftUpLeg", {0.5f, -41.0f, 1.0f}},
    {"mixamorig:LeftFoot", "mixamorig:LeftLeg", {0.5f, -43.0f, -4.0f}},
    {"mixamorig:LeftToeBase", "mixamorig:LeftFoot", {0.5f, -7.0f, 13.0f}},
    {"mixamorig:RightUpLeg", "mixamorig:Hips", {-9.0f, -5.0f, 0.0f}},
    {"mixamorig:RightLeg", "mixamorig:RightUpLeg", {-0.5f, -41.0f, 1.0f}},
    {"mixamorig:RightFoot", "mixamorig:RightLeg", {-0.5f, -43.0f, -4.0f}},
    {"mixamorig:RightToeBase", "mixamorig:RightFoot", {-0.5f, -7.0f, 13.0f}},
};

cg_quat multiply(const cg_quat& a, const cg_quat& b) {
    return cg_quat{a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                   a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                   a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                   a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

cg_vec3 rotate(const cg_quat& q, const cg_vec3& v) {
    const cg_quat p = multiply(multiply(q, cg_quat{v.x, v.y, v.z, 0.0f}),
                               cg_quat{-q.x, -q.y, -q.z, q.w});
    return cg_vec3{p.x, p.y, p.z};
}

cg_vec3 add(const cg_vec3& a, const cg_vec3& b) { return cg_vec3{a.x + b.x, a.y + b.y, a.z + b.z}; }

// Forward kinematics: each bone's rotation and position relative to the character.
void globals(const std::vector<cg_quat>& locals, const std::vector<std::int32_t>& parents,
             const std::vector<cg_vec3>& offsets, std::vector<cg_quat>& rotations,
             std::vector<cg_vec3>& positions) {
    rotations.resize(locals.size());
    positions.resize(locals.size());
    for (std::size_t i = 0; i < locals.size(); i++) {
        if (parents[i] < 0) {
            rotations[i] = locals[i];
            positions[i] = offsets[i];
        } else {
            const auto p = static_cast<std::size_t>(parents[i]);
            rotations[i] = multiply(rotations[p], locals[i]);
            positions[i] = add(positions[p], rotate(rotations[p], offsets[i]));
        }
    }
}

// The angle between the head's forward (+Z of its bone) and the direction to `target`.
double angle_to(const std::vector<cg_quat>& locals, const std::vector<std::int32_t>& parents,
                const std::vector<cg_vec3>& offsets, std::size_t head, const cg_vec3& target) {
    std::vector<cg_quat> rotations;
    std::vector<cg_vec3> positions;
    globals(locals, parents, offsets, rotations, positions);
    const cg_vec3 forward = rotate(rotations[head], cg_vec3{0.0f, 0.0f, 1.0f});
    const cg_vec3 to{target.x - positions[head].x, target.y - positions[head].y,
                     target.z - positions[head].z};
    const double dot = forward.x * to.x + forward.y * to.y + forward.z * to.z;
    const double length = std::sqrt(static_cast<double>(to.x * to.x + to.y * to.y + to.z * to.z)) *
                          std::sqrt(static_cast<double>(
                              forward.x * forward.x + forward.y * forward.y + forward.z * forward.z));
    return std::acos(dot / length) * 180.0 / 3.14159265358979;
}

}  // namespace

int main() {
    // The skeleton as an engine holds it: names, parent indices, offsets.
    std::vector<std::string> names;
    std::vector<std::int32_t> parents;
    std::vector<cg_vec3> offsets;
    for (const Bone& bone : kSkeleton) {
        std::int32_t parent = -1;
        for (std::size_t i = 0; bone.parent != nullptr && i < names.size(); i++) {
            if (names[i] == bone.parent) parent = static_cast<std::int32_t>(i);
        }
        names.emplace_back(bone.name);
        parents.push_back(parent);
        offsets.push_back(bone.offset);
    }

    // The crowd: centimetres, Y up, +Z forward (the defaults but the units).
    cg_crowd_config config = crowdgaze::crowd_config();
    config.max_characters = 4;
    config.units_per_metre = 100.0f;
    crowdgaze::Crowd crowd(config);

    // One call maps the skeleton: no bone map, axes detected, the crowd's axes and units.
    const crowdgaze::Rig rig(names, parents, offsets, 100.0f, std::string(), &config);
    const std::string report = rig.report();
    std::printf("%s\n", report.substr(0, report.find('\n')).c_str());
    const std::vector<std::uint32_t> chain_bones = rig.chain_bones();
    const std::vector<cg_bone_role> roles = rig.bone_roles();
    const std::size_t head = chain_bones.at(chain_bones.size() - 3);  // then the two eyes
    if (rig.joint_count() != 7 || rig.bone_count() != names.size() ||
        names[head] != "mixamorig:Head" || roles[head] != CG_BONE_ROLE_HEAD ||
        roles[chain_bones.back()] != CG_BONE_ROLE_RIGHT_EYE) {
        std::fprintf(stderr, "unexpected mapping:\n%s", report.c_str());
        return 1;
    }

    // The character, with the rig's chain, at the origin facing +Z; it looks at a point
    // ahead and to its left (+X), at eye height.
    const cg_chain_desc chain = rig.chain();
    cg_character_desc desc = crowdgaze::character_desc(cg_vec3{0.0f, 0.0f, 0.0f});
    desc.chain = &chain;
    const std::uint32_t id = crowd.add_character(desc);
    const cg_vec3 target{150.0f, 165.0f, 150.0f};
    crowd.look_at(id, target);

    // The animation's pose this frame (the rest pose here), the base pose, the joints.
    const std::vector<cg_quat> animated(names.size(), cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
    std::vector<cg_quat> posed = animated;
    std::vector<cg_quat> base;
    std::vector<cg_quat> joints(rig.joint_count());
    const double before = angle_to(posed, parents, offsets, head, target);
    cg_entity_state state = crowdgaze::entity_state();
    state.id = id;
    for (int frame = 1; frame <= 60; frame++) {
        posed = animated;
        rig.base_pose(posed, base);
        crowd.set_base_pose(id, base);
        crowd.push_frame(frame / 30.0, {&state, 1});
        crowd.step(1.0f / 30.0f);
        crowd.read_joints(0, 1, joints);  // row 0: the crowd's only character
        rig.write_joints(joints, posed);
    }
    const double after = angle_to(posed, parents, offsets, head, target);
    std::printf("head off the target: %.1f deg at rest, %.1f deg after 2 s\n", before, after);
    if (!(after < before - 20.0)) {
        return 1;
    }

    // A skeleton that does not map says why, and which override fixes it.
    std::vector<std::string> renamed = names;
    renamed[5] = "Skull";
    crowdgaze::Rig unmapped;
    const cg_status status = crowdgaze::Rig::try_create(
        renamed, parents, offsets, 100.0f, std::string(), &config, {}, unmapped);
    std::printf("without a head: %s\n", crowdgaze::last_error_message().c_str());
    if (status != CG_STATUS_INVALID_ARGUMENT || unmapped) {
        return 1;
    }
    const crowdgaze::Rig fixed(renamed, parents, offsets, 100.0f, "Skull=head", &config);
    if (fixed.chain_bones() != chain_bones) {
        return 1;
    }
    std::printf("ok\n");
    return 0;
}
