// cpp_no_exceptions.cpp: the C++ wrapper built with -fno-exceptions, as engine modules
// (Unreal's by default) are: only the `try_` forms, which return the cg_status. A crowd of
// two characters facing each other, each looking at the other; a failing call reports its
// status and message and changes nothing. Then a UE5-style skeleton mapped to a gaze
// chain by a `crowdgaze::Rig`, driven a frame, with the `try_` forms too.
#include "crowdgaze.hpp"

#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace {

bool ok(cg_status status, const char* what) {
    if (status != CG_STATUS_OK) {
        std::fprintf(stderr, "%s: %s\n", what, crowdgaze::last_error_message().c_str());
        return false;
    }
    return true;
}

// A UE5-style skeleton (Z up, facing +Y, centimetres) mapped with no overrides, added to
// `crowd` (Z up, X forward: the rig turns the chain and the poses into its axes) and
// driven one frame: bone rotations -> base pose -> step -> joints -> bone rotations.
bool rig_frame(crowdgaze::Crowd& crowd, const cg_crowd_config& config) {
    static const char* const names[] = {"root",     "pelvis",     "spine_01",   "spine_02",
                                        "spine_03", "spine_04",   "spine_05",   "neck_01",
                                        "neck_02",  "head",       "clavicle_l", "clavicle_r",
                                        "thigh_l",  "thigh_r"};
    static const std::int32_t parents[] = {-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 6, 6, 1, 1};
    static const cg_vec3 offsets[] = {
        {0, 0, 0},    {0, 0, 98},  {0, 0, 7},    {0, -0.5f, 8}, {0, -0.5f, 8},
        {0, -0.5f, 8}, {0, -0.5f, 8}, {0, -1, 9}, {0, 1.5f, 7},  {0, 1.5f, 7},
        {-2.5f, 2, 6}, {2.5f, 2, 6}, {-9, 0, -5},  {9, 0, -5}};
    crowdgaze::Rig rig;
    if (!ok(crowdgaze::Rig::try_create(names, parents, offsets, 100.0f, nullptr, &config, {},
                                       rig),
            "rig")) {
        return false;
    }
    std::array<char, 128> line{};
    rig.report(line);  // cut to the buffer: the first line fits
    std::uint32_t joint_count = 0;
    std::array<std::uint32_t, 14> roles{};
    cg_chain_desc chain{};
    if (!ok(rig.try_joint_count(joint_count), "joint count") ||
        !ok(rig.try_bone_roles(roles), "roles") || !ok(rig.try_chain(chain), "chain") ||
        joint_count != 8 || chain.joint_count != 8 || roles[9] != CG_BONE_ROLE_HEAD) {
        return false;
    }
    std::printf("%.*s\n", static_cast<int>(std::string(line.data()).find('\n')), line.data());
    cg_character_desc desc = crowdgaze::character_desc(cg_vec3{0.0f, 300.0f, 0.0f});
    desc.chain = &chain;
    std::uint32_t id = CG_NO_TARGET;
    std::size_t row = 0;
    if (!ok(crowd.try_add_character(desc, id), "add") ||
        !ok(crowd.try_character_count(row), "count")) {
        return false;
    }
    row -= 1;  // the newest character is the last row
    std::array<cg_quat, 14> bones{};
    bones.fill(cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
    std::array<cg_quat, 8> base{};
    std::array<cg_quat, 8> joints{};
    if (!ok(rig.try_base_pose(bones, base), "base pose") ||
        !ok(crowd.try_set_base_pose(id, base), "set base pose") ||
        !ok(crowd.try_set_gaze_target(id, crowdgaze::gaze_target_point({300, 300, 160})),
            "target") ||
        !ok(crowd.try_step(1.0f / 30.0f), "step") ||
        !ok(crowd.try_read_joints(static_cast<std::uint32_t>(row), 1, joints), "joints") ||
        !ok(rig.try_write_joints(joints, bones), "write joints")) {
        return false;
    }
    // Too few bone rotations: a status, and nothing written.
    const cg_status status =
        rig.try_base_pose(crowdgaze::Span<const cg_quat>(bones.data(), 3), base);
    std::printf("try_base_pose(3 bones): %s\n", crowdgaze::status_string(status));
    return status == CG_STATUS_INVALID_ARGUMENT;
}

}  // namespace

int main() {
    static_assert(noexcept(std::declval<crowdgaze::Crowd&>().try_step(0.0f)), "try_ is noexcept");
    cg_crowd_config config = crowdgaze::crowd_config();
    config.max_characters = 3;  // two walkers, then a rigged character
    config.units_per_metre = 100.0f;  // Unreal: centimetres, Z up, X forward
    config.up_axis = CG_AXIS_POSITIVE_Z;
    config.forward_axis = CG_AXIS_POSITIVE_X;
    crowdgaze::Crowd crowd;
    if (!ok(crowdgaze::Crowd::try_create(config, crowd), "create")) return 1;

    std::array<std::uint32_t, 2> ids{};
    const std::array<cg_vec3, 2> positions{cg_vec3{0.0f, 0.0f, 0.0f}, cg_vec3{300.0f, 0.0f, 0.0f}};
    const std::array<float, 2> headings{0.0f, 3.14159265f};
    for (std::size_t i = 0; i < 2; i++) {
        if (!ok(crowd.try_add_character(crowdgaze::character_desc(positions[i], headings[i]), ids[i]),
                "add")) {
            return 1;
        }
    }
    for (std::size_t i = 0; i < 2; i++) {
        if (!ok(crowd.try_set_gaze_target(ids[i], crowdgaze::gaze_target_entity(ids[1 - i])),
                "target")) {
            return 1;
        }
    }
    std::vector<cg_entity_state> states;
    for (std::size_t i = 0; i < 2; i++) {
        cg_entity_state state = crowdgaze::entity_state();
        state.id = ids[i];
        state.position = positions[i];
        state.heading = headings[i];
        states.push_back(state);
    }
    std::size_t total = 0;
    if (!ok(crowd.try_joint_total(0, 2, total), "joint total")) return 1;
    std::vector<cg_quat> joints(total);
    std::array<cg_eye_info, 2> eyes{};
    std::array<cg_eyelids, 2> lids{};
    for (int frame = 1; frame <= 30; frame++) {
        if (!ok(crowd.try_push_frame(frame / 30.0, states), "push") ||
            !ok(crowd.try_step(1.0f / 30.0f), "step") ||
            !ok(crowd.try_read_joints(0, 2, joints), "joints") ||
            !ok(crowd.try_read_eyes(0, 2, eyes), "eyes") ||
            !ok(crowd.try_read_eyelids(0, 2, lids), "eyelids")) {
            return 1;
        }
    }
    std::printf("joints %zu, eye directions x %+.2f and %+.2f\n", joints.size(),
                static_cast<double>(eyes[0].left_direction.x),
                static_cast<double>(eyes[1].left_direction.x));
    if (lids[0].character != eyes[0].character || lids[0].left_closure < 0.0f ||
        lids[0].left_closure > 1.0f) {
        return 1;
    }
    if (joints.size() != 20 || eyes[0].left_direction.x < 0.99f || eyes[1].left_direction.x > -0.99f) {
        return 1;
    }
    // The two form a conversation: from the next step they look at each other as people
    // talking do.
    std::uint32_t group = CG_NO_TARGET;
    if (!ok(crowd.try_set_conversation(ids, group), "conversation") || group == CG_NO_TARGET) {
        return 1;
    }
    // A failure is a status and a message; the crowd is unchanged.
    const cg_status status = crowd.try_step(-1.0f);
    std::printf("try_step(-1): %s (%s)\n", crowdgaze::status_string(status),
                crowdgaze::last_error_message().c_str());
    std::size_t count = 0;
    if (status != CG_STATUS_INVALID_ARGUMENT || !ok(crowd.try_character_count(count), "count") ||
        count != 2) {
        return 1;
    }
    crowdgaze::ViewBlender blender;
    if (crowdgaze::ViewBlender::try_create(crowdgaze::view_blender_config(0, 1), blender) !=
            CG_STATUS_INVALID_ARGUMENT ||
        blender) {
        return 1;
    }
    if (!rig_frame(crowd, config)) return 1;
    std::printf("ok\n");
    return 0;
}
