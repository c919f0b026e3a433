// cpp_wrapper.cpp: the C++17 wrapper (bindings/cpp/crowdgaze.hpp) as an engine uses it —
// a crowd created from its config, characters and an object added, frames pushed, steps,
// gaze, joints, deltas and eyes read, a base pose, explicit gaze targets, blinks and
// eyelids, a conversation, the street preset and gaze following, an offline plan and its constraints, a view blender (keys,
// cameras, weights, evaluate), the dual quaternion helpers, errors as exceptions and as
// statuses, and the owners' move semantics.
#include "crowdgaze.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

int failures = 0;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            failures++;                                                                  \
        }                                                                                \
    } while (0)

constexpr float kPi = 3.14159265358979f;
constexpr float kDegree = kPi / 180.0f;

cg_quat multiply(const cg_quat& a, const cg_quat& b) {
    return cg_quat{a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                   a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                   a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                   a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

cg_quat yaw_quat(float angle) {  // about +Y
    return cg_quat{0.0f, std::sin(angle / 2.0f), 0.0f, std::cos(angle / 2.0f)};
}

// Yaw (degrees, counter-clockwise about +Y from +Z) of +Z rotated by q.
float yaw_of(const cg_quat& q) {
    const float x = 2.0f * (q.x * q.z + q.w * q.y);
    const float z = 1.0f - 2.0f * (q.x * q.x + q.y * q.y);
    return std::atan2(x, z) / kDegree;
}

// Angle in degrees between two rotations (from the vector part of a * conj(b), which keeps
// its precision for small angles where acos of the dot product does not).
float angle_between(const cg_quat& a, const cg_quat& b) {
    const cg_quat d = multiply(a, cg_quat{-b.x, -b.y, -b.z, b.w});
    const double v = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
    return static_cast<float>(2.0 * std::atan2(v, std::fabs(double(d.w))) / kDegree);
}

float length(const cg_vec3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

float angle_between(const cg_vec3& a, const cg_vec3& b) {
    float cosine = (a.x * b.x + a.y * b.y + a.z * b.z) / (length(a) * length(b));
    cosine = cosine > 1.0f ? 1.0f : (cosine < -1.0f ? -1.0f : cosine);
    return std::acos(cosine) / kDegree;
}

static_assert(!std::is_copy_constructible_v<crowdgaze::Crowd>, "Crowd is move-only");
static_assert(std::is_nothrow_move_constructible_v<crowdgaze::Crowd>, "Crowd moves");
static_assert(!std::is_copy_assignable_v<crowdgaze::ViewBlender>, "ViewBlender is move-only");
static_assert(std::is_nothrow_move_assignable_v<crowdgaze::ViewBlender>, "ViewBlender moves");
static_assert(std::is_base_of_v<crowdgaze::Owner<cg_crowd, cg_crowd_destroy>, crowdgaze::Crowd>,
              "one owner template for every handle");
static_assert(std::is_base_of_v<crowdgaze::Owner<cg_view_blender, cg_view_blender_destroy>,
                                crowdgaze::ViewBlender>,
              "one owner template for every handle");

// One character turns its gaze 60 degrees to the left; two walkers pass by.
void crowd_gaze() {
    cg_crowd_config config = crowdgaze::crowd_config();
    config.seed = 7;
    config.max_characters = 3;
    config.max_objects = 1;
    crowdgaze::Crowd crowd(config);
    CHECK(crowd.config().seed == 7);

    const std::uint32_t watcher = crowd.add_character_at({0.0f, 0.0f, 0.0f});
    const std::uint32_t left = crowd.add_character_at({-1.5f, 0.0f, 6.0f}, kPi);
    const std::uint32_t right = crowd.add_character(crowdgaze::character_desc({1.5f, 0.0f, -6.0f}));
    cg_object_desc lamp = crowdgaze::object_desc();
    lamp.position = {3.0f, 0.0f, 2.0f};
    lamp.look_at_height = 3.0f;
    const std::uint32_t lamp_id = crowd.add_object(lamp);
    CHECK(crowd.character_count() == 3);
    const std::size_t joints_per_chain = crowd.joint_total(0, 1);
    CHECK(joints_per_chain == 10);
    CHECK(crowd.joint_total(0, 3) == 30);

    // The watcher's animation bends its lowest spine joint 10 degrees forward (about +X).
    std::vector<cg_quat> base(joints_per_chain, cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
    base[0] = cg_quat{std::sin(5.0f * kDegree), 0.0f, 0.0f, std::cos(5.0f * kDegree)};
    crowd.set_base_pose(watcher, base);
    std::vector<std::uint32_t> walkers{left, right};
    std::vector<cg_quat> walker_bases(2 * joints_per_chain, cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
    crowd.set_base_poses(walkers, walker_bases);

    // Look at a point 60 degrees to the left (Y up, +Z forward: left is +X) at eye height.
    const cg_vec3 point{3.0f * std::sin(60.0f * kDegree), 1.6f, 3.0f * std::cos(60.0f * kDegree)};
    crowd.set_gaze_target(watcher, crowdgaze::gaze_target_point(point));

    std::array<cg_entity_state, 2> states{crowdgaze::entity_state(left, {-1.5f, 0.0f, 6.0f}),
                                          crowdgaze::entity_state(right, {1.5f, 0.0f, -6.0f})};
    std::vector<cg_gaze_info> gaze(3);
    std::vector<cg_quat> joints(crowd.joint_total(0, 3));
    const float dt = 1.0f / 30.0f;
    for (int frame = 1; frame <= 90; frame++) {
        const double t = frame * static_cast<double>(dt);
        states[0].position.z = 6.0f - 1.3f * static_cast<float>(t);
        states[1].position.z = -6.0f + 1.3f * static_cast<float>(t);
        if (frame % 3 == 0) {
            // The ranged push, as a job system would call it (here on one thread).
            crowd.begin_push(t);
            crowd.push_range(crowdgaze::Span<const cg_entity_state>(states.data(), 1));
            CHECK(crowd.try_push_range(states) == CG_STATUS_WRONG_STATE);  // states[0] again
            crowd.push_range(crowdgaze::Span<const cg_entity_state>(states.data() + 1, 1));
            crowd.end_push();
        } else {
            crowd.push_frame(t, states);
        }
        if (frame % 2 == 0) {
            crowd.step(dt);
        } else {
            // The ranged form, as a job system would call it (here on one thread).
            crowd.begin_step(dt);
            crowd.step_range(1, 2);
            CHECK(crowd.try_step_range(2, 1) == CG_STATUS_WRONG_STATE);  // already stepped
            crowd.end_step();  // steps character 0, which no range covered
        }
        CHECK(crowd.read_gaze(gaze) == 3);
        crowd.read_joints(0, 3, joints);
    }
    CHECK(gaze[0].character == watcher && gaze[1].character == left &&
          gaze[2].character == right);

    // The eyes reached the target (the head and torso turn part of the way).
    cg_quat world{0.0f, 0.0f, 0.0f, 1.0f};
    for (int i = 0; i < 8; i++) world = multiply(world, joints[static_cast<std::size_t>(i)]);
    const float head_yaw = yaw_of(world);
    const float eye_yaw = 0.5f * (yaw_of(multiply(world, joints[8])) + yaw_of(multiply(world, joints[9])));
    std::printf("watcher after 3 s: head yaw %.1f deg, eye yaw %.1f deg (target 60)\n",
                static_cast<double>(head_yaw), static_cast<double>(eye_yaw));
    CHECK(eye_yaw > 57.0f && eye_yaw < 63.0f);
    CHECK(head_yaw > 20.0f && head_yaw < eye_yaw);

    // Final = base * delta, joint by joint.
    std::vector<cg_quat> deltas(joints_per_chain);
    crowd.read_joint_deltas(0, 1, deltas);
    float worst = 0.0f;
    for (std::size_t i = 0; i < joints_per_chain; i++) {
        const float error = angle_between(joints[i], multiply(base[i], deltas[i]));
        worst = error > worst ? error : worst;
    }
    std::printf("final vs base * delta: %.5f deg\n", static_cast<double>(worst));
    CHECK(worst < 0.01f);

    // The eyes look at the point.
    std::array<cg_eye_info, 1> eyes{};
    crowd.read_eyes(0, 1, eyes);
    const cg_vec3 to_point{point.x - eyes[0].left_origin.x, point.y - eyes[0].left_origin.y,
                           point.z - eyes[0].left_origin.z};
    const float eye_error = angle_between(eyes[0].left_direction, to_point);
    std::printf("left eye off the target by %.2f deg\n", static_cast<double>(eye_error));
    CHECK(eyes[0].character == watcher);
    CHECK(eye_error < 2.0f);

    // The score of the lamp for the watcher, and an override cleared.
    const cg_score_breakdown score = crowd.score(watcher, lamp_id);
    CHECK(std::fabs(score.distance - std::sqrt(13.0f)) < 1e-3f);
    crowd.clear_gaze_target(watcher);
    cg_character_params params = crowd.character_params(watcher);
    params.attention_fraction = 0.5f;
    crowd.set_character_params(watcher, params);
    CHECK(std::fabs(crowd.character_params(watcher).attention_fraction - 0.5f) < 1e-6f);
    crowd.set_impact(lamp_id, 2.0f);
    crowd.remove_entity(lamp_id);
    CHECK(crowd.character_count() == 3);

    // Errors: as exceptions carrying the status and the message, or as statuses.
    bool thrown = false;
    try {
        crowd.step(-1.0f);
    } catch (const crowdgaze::Error& error) {
        thrown = true;
        std::printf("step(-1) threw: %s\n", error.what());
        CHECK(error.status() == CG_STATUS_INVALID_ARGUMENT);
        CHECK(!error.message().empty());
    }
    CHECK(thrown);
    CHECK(crowd.try_step(std::nanf("")) == CG_STATUS_NON_FINITE);
    CHECK(crowd.try_remove_entity(lamp_id) == CG_STATUS_NOT_FOUND);
    std::vector<cg_quat> too_small(5);
    CHECK(crowd.try_read_joints(0, 1, too_small) == CG_STATUS_INVALID_ARGUMENT);
    thrown = false;
    try {
        crowd.set_gaze_target(12345u, crowdgaze::gaze_target_entity(watcher));
    } catch (const crowdgaze::Error& error) {
        thrown = error.status() == CG_STATUS_NOT_FOUND;
    }
    CHECK(thrown);
    CHECK(crowd.character_count() == 3);  // failed calls changed nothing

    // The viewer as an entity, and a slower attention update for one character.
    const std::uint32_t viewer = crowd.set_viewer({0.0f, 1.7f, 2.0f}, 2.0f);
    CHECK(viewer != CG_NO_TARGET && viewer != watcher && viewer != lamp_id);
    crowd.set_viewer({0.5f, 1.7f, 2.0f});
    crowd.set_attention_period(left, 2);
    CHECK(crowd.try_set_attention_period(left, 65) == CG_STATUS_INVALID_ARGUMENT);
    crowd.step(dt);

    // Ownership: moves, release and adoption.
    crowdgaze::Crowd moved = std::move(crowd);
    CHECK(!crowd && moved && moved.character_count() == 3);  // NOLINT: use after move on purpose
    cg_crowd* handle = moved.release();
    CHECK(!moved && handle != nullptr);
    crowdgaze::Crowd adopted(handle);
    CHECK(adopted.raw() == handle);
}

// Blinks and eyelids: the blink settings of the config, one cg_eyelids per character in
// read_gaze's order, closures in [0, 1] with blinks seen over 20 s, and refused outputs.
void eyelids() {
    cg_crowd_config config = crowdgaze::crowd_config();
    config.seed = 11;
    config.max_characters = 3;
    config.max_objects = 0;
    config.blink_rate = 20.0f;
    config.eye_motion = CG_EYE_MOTION_MAIN_SEQUENCE;
    crowdgaze::Crowd crowd(config);
    const cg_crowd_config stored = crowd.config();
    CHECK(stored.blink_rate == 20.0f && stored.eye_motion == CG_EYE_MOTION_MAIN_SEQUENCE);
    CHECK(stored.blink_rate_spread == 0.5f && stored.lid_gain == 1.0f);

    std::array<std::uint32_t, 3> ids{};
    for (std::size_t i = 0; i < ids.size(); i++) {
        ids[i] = crowd.add_character_at({2.0f * static_cast<float>(i), 0.0f, 0.0f},
                                        kPi * static_cast<float>(i) / 3.0f);
    }
    std::array<cg_eyelids, 3> lids{};
    float most_closed = 0.0f;
    bool in_range = true;
    for (int frame = 0; frame < 600; frame++) {  // 20 s at 30 Hz
        crowd.step(1.0f / 30.0f);
        crowd.read_eyelids(0, 3, lids);
        for (const cg_eyelids& lid : lids) {
            in_range = in_range && lid.left_closure >= 0.0f && lid.left_closure <= 1.0f &&
                       lid.right_closure >= 0.0f && lid.right_closure <= 1.0f &&
                       std::isfinite(lid.left_lid_pitch) && std::isfinite(lid.right_lid_pitch);
            most_closed = lid.left_closure > most_closed ? lid.left_closure : most_closed;
        }
    }
    std::printf("eyelids over 20 s: most closed %.2f\n", static_cast<double>(most_closed));
    CHECK(in_range);
    CHECK(most_closed > 0.5f);
    CHECK(lids[0].character == ids[0] && lids[1].character == ids[1] &&
          lids[2].character == ids[2]);
    std::array<cg_eyelids, 1> last{};
    crowd.read_eyelids(2, 1, last);
    CHECK(last[0].character == ids[2]);

    // Too small an output, or a range past the last character: refused, nothing written.
    std::array<cg_eyelids, 2> too_small{};
    too_small[0].character = CG_NO_TARGET;
    CHECK(crowd.try_read_eyelids(0, 3, too_small) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(crowd.try_read_eyelids(2, 2, too_small) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(too_small[0].character == CG_NO_TARGET);
    bool thrown = false;
    try {
        crowd.read_eyelids(0, 3, too_small);
    } catch (const crowdgaze::Error& error) {
        thrown = error.status() == CG_STATUS_INVALID_ARGUMENT && !error.message().empty();
    }
    CHECK(thrown);

    // Blink settings out of range are refused at creation.
    cg_crowd_config bad = crowdgaze::crowd_config();
    bad.eye_motion = 7;
    crowdgaze::Crowd refused;
    CHECK(crowdgaze::Crowd::try_create(bad, refused) == CG_STATUS_INVALID_ARGUMENT && !refused);
    bad = crowdgaze::crowd_config();
    bad.blink_rate = std::nanf("");
    CHECK(crowdgaze::Crowd::try_create(bad, refused) == CG_STATUS_NON_FINITE && !refused);
}

// The street preset and gaze following: five characters stare at a window (overriding
// targets), passers-by standing in front of them glance there too; following reads back,
// refuses an unknown id without writing, and bad follow settings are refused.
void street_following() {
    cg_crowd_config config = crowdgaze::street_config();
    CHECK(config.follow_enabled == 1 && config.max_distance == 17.0f);
    CHECK(crowdgaze::crowd_config().follow_enabled == 0);
    config.seed = 1969;
    config.max_characters = 15;
    config.max_objects = 0;
    crowdgaze::Crowd crowd(config);
    CHECK(crowd.config().follow_enabled == 1);
    const cg_vec3 window{0.0f, 12.0f, -6.0f};
    std::vector<std::uint32_t> starers, passers_by;
    for (int i = 0; i < 15; i++) {
        cg_character_desc desc = crowdgaze::character_desc();
        desc.attention_model = CG_ATTENTION_MODEL_STREET;
        if (i < 5) {
            desc.position = {-1.0f + 0.5f * static_cast<float>(i), 0.0f, 0.0f};
            starers.push_back(crowd.add_character(desc));
            crowd.set_gaze_target(starers.back(), crowdgaze::gaze_target_point(window));
        } else {
            desc.position = {-4.0f + 2.0f * static_cast<float>(i % 5), 0.0f,
                             4.0f + static_cast<float>(i / 5)};
            desc.heading = kPi;
            passers_by.push_back(crowd.add_character(desc));
        }
    }
    bool on_the_window = true;
    for (int frame = 1; frame <= 300; frame++) {
        crowd.step(1.0f / 30.0f);
        for (std::uint32_t id : passers_by) {
            const auto f = crowd.following(id);
            if (f.following) {
                on_the_window = on_the_window && std::fabs(f.point.y - window.y) < 1e-4f &&
                                std::fabs(f.point.z - window.z) < 1e-4f;
            }
        }
    }
    int followers = 0;
    for (std::uint32_t id : passers_by) followers += crowd.following(id).glances > 0;
    CHECK(on_the_window);
    CHECK(followers >= 3);
    CHECK(crowd.following(starers[0]).glances == 0 && !crowd.following(starers[0]).following);
    std::printf("street: %d of 10 passers-by glanced at the window\n", followers);

    crowdgaze::Crowd::Following untouched;
    untouched.glances = 77u;
    CHECK(crowd.try_following(12345u, untouched) == CG_STATUS_NOT_FOUND);
    CHECK(untouched.glances == 77u && !untouched.following);

    cg_crowd_config bad = crowdgaze::street_config();
    bad.follow_max_probability = 1.5f;
    crowdgaze::Crowd refused;
    CHECK(crowdgaze::Crowd::try_create(bad, refused) == CG_STATUS_INVALID_ARGUMENT && !refused);
    bool named = false;
    try {
        crowdgaze::Crowd thrown(bad);
    } catch (const crowdgaze::Error& error) {
        named = error.message().find("follow_max_probability") != std::string::npos;
    }
    CHECK(named);
}

// A conversation: two characters facing each other form a group, the first talking; the
// group is read back, ends when one of them is removed, and a group of one is refused.
void conversation() {
    cg_crowd_config config = crowdgaze::crowd_config();
    config.seed = 5;
    config.max_characters = 3;
    config.max_objects = 0;
    crowdgaze::Crowd crowd(config);
    const std::uint32_t speaker = crowd.add_character_at({0.0f, 0.0f, 0.0f});
    const std::uint32_t listener = crowd.add_character_at({0.0f, 0.0f, 1.2f}, kPi);
    const std::uint32_t passer_by = crowd.add_character_at({4.0f, 0.0f, 3.0f}, -kPi / 2.0f);

    const std::array<std::uint32_t, 2> pair{speaker, listener};
    const std::uint32_t group = crowd.set_conversation(pair);
    CHECK(group != CG_NO_TARGET);
    CHECK(crowd.conversation(speaker) == group && crowd.conversation(listener) == group);
    CHECK(crowd.conversation(passer_by) == CG_NO_TARGET);

    std::array<cg_entity_state, 3> states{
        crowdgaze::entity_state(speaker, {0.0f, 0.0f, 0.0f}),
        crowdgaze::entity_state(listener, {0.0f, 0.0f, 1.2f}),
        crowdgaze::entity_state(passer_by, {4.0f, 0.0f, 3.0f})};
    states[0].flags |= CG_STATE_TALKING;
    states[1].heading = kPi;
    states[2].heading = -kPi / 2.0f;
    std::array<cg_gaze_info, 3> gaze{};
    for (int frame = 1; frame <= 60; frame++) {
        crowd.push_frame(frame / 30.0, states);
        crowd.step(1.0f / 30.0f);
        crowd.read_gaze(gaze);
    }
    CHECK(gaze[1].character == listener);

    // A group of one: refused, as a status or an exception; nothing changed.
    const std::array<std::uint32_t, 1> alone{passer_by};
    std::uint32_t refused = 12345u;
    CHECK(crowd.try_set_conversation(alone, refused) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(refused == 12345u && crowd.conversation(passer_by) == CG_NO_TARGET);
    bool thrown = false;
    try {
        crowd.set_conversation(alone);
    } catch (const crowdgaze::Error& error) {
        thrown = error.status() == CG_STATUS_INVALID_ARGUMENT && !error.message().empty();
    }
    CHECK(thrown);
    CHECK(crowd.try_conversation(12345u, refused) == CG_STATUS_NOT_FOUND);

    // The listener leaves: a group left with one member ends.
    crowd.remove_entity(listener);
    CHECK(crowd.conversation(speaker) == CG_NO_TARGET);
    CHECK(crowd.try_remove_conversation(group) == CG_STATUS_NOT_FOUND);
    std::printf("conversation %u of 2: ended when the listener left\n", group);
}

// An offline plan of two walkers crossing, and its constraints.
void offline_plan() {
    cg_crowd_config config = crowdgaze::crowd_config();
    config.max_characters = 2;
    config.max_objects = 0;
    config.max_recorded_states = 2 * 300;
    crowdgaze::Crowd crowd;
    CHECK(crowdgaze::Crowd::try_create(config, crowd) == CG_STATUS_OK && crowd);
    const std::uint32_t a = crowd.add_character_at({-0.8f, 0.0f, -8.0f});
    const std::uint32_t b = crowd.add_character_at({0.8f, 0.0f, 8.0f}, kPi);
    for (std::uint32_t id : {a, b}) {
        cg_character_params params = crowd.character_params(id);
        params.attention_fraction = 0.6f;
        crowd.set_character_params(id, params);
    }
    std::array<cg_entity_state, 2> states{crowdgaze::entity_state(a, {}),
                                          crowdgaze::entity_state(b, {})};
    for (int frame = 0; frame < 300; frame++) {
        const float t = static_cast<float>(frame) / 30.0f;
        states[0].position = {-0.8f, 0.0f, -8.0f + 1.6f * t};
        states[1].position = {0.8f, 0.0f, 8.0f - 1.6f * t};
        crowd.push_frame(t, states);
    }
    crowd.plan();
    CHECK(crowd.try_push_frame(10.0, states) == CG_STATUS_WRONG_STATE);
    std::size_t planned = 0;
    for (std::uint32_t id : {a, b}) {
        const std::vector<cg_constraint> constraints = crowd.constraints(id);
        CHECK(constraints.size() == crowd.read_constraints(id, {}));
        for (const cg_constraint& c : constraints) {
            CHECK(c.entity == (id == a ? b : a));
            CHECK(c.begin >= 0.0 && c.begin < c.end && c.end <= 10.0);
        }
        planned += constraints.size();
    }
    std::printf("planned constraints: %zu\n", planned);
    CHECK(planned >= 1);
    crowd.step(1.0f / 30.0f);
    crowd.clear_plan();
    crowd.push_frame(10.0, states);
}

void dual_quaternions() {
    const cg_quat rotation = yaw_quat(40.0f * kDegree);
    const cg_vec3 translation{1.0f, 2.0f, 3.0f};
    const cg_dualquat q = crowdgaze::dualquat_from_rt(rotation, translation);
    const std::array<float, 16> matrix = crowdgaze::dualquat_to_matrix(q);
    CHECK(std::fabs(matrix[12] - 1.0f) < 1e-5f && std::fabs(matrix[13] - 2.0f) < 1e-5f &&
          std::fabs(matrix[14] - 3.0f) < 1e-5f);
    const crowdgaze::RigidTransform back = crowdgaze::dualquat_to_rt(crowdgaze::dualquat_from_matrix(matrix));
    CHECK(angle_between(back.rotation, rotation) < 0.01f);
    CHECK(std::fabs(back.translation.z - 3.0f) < 1e-5f);

    // Two transforms, blended half and half: the yaw halves, DLB and DIB agree.
    const std::array<cg_dualquat, 2> inputs{
        crowdgaze::dualquat_from_rt(yaw_quat(0.0f), {0.0f, 0.0f, 0.0f}),
        crowdgaze::dualquat_from_rt(yaw_quat(80.0f * kDegree), {2.0f, 0.0f, 0.0f})};
    const std::array<float, 2> halves{0.5f, 0.5f};
    const cg_dualquat dlb = crowdgaze::blend_dlb(inputs, halves);
    cg_dualquat dib{};
    CHECK(crowdgaze::blend_dib(inputs, halves, dib));
    CHECK(std::fabs(yaw_of(dlb.real) - 40.0f) < 0.01f);
    CHECK(std::fabs(yaw_of(dib.real) - 40.0f) < 0.01f);
    std::array<cg_dualquat, 1> pose{};
    crowdgaze::blend_pose_dlb({inputs.data(), inputs.size()}, halves, pose);
    CHECK(angle_between(pose[0].real, dlb.real) < 0.01f);
    CHECK(crowdgaze::blend_pose_dib(inputs, halves, pose));
    CHECK(angle_between(pose[0].real, dib.real) < 0.01f);

    // Sizes that do not match, and a bad weight.
    const std::array<float, 1> one{1.0f};
    cg_dualquat out{};
    CHECK(crowdgaze::try_blend_dlb(inputs, one, out) == CG_STATUS_INVALID_ARGUMENT);
    const std::array<float, 2> negative{-1.0f, 2.0f};
    CHECK(crowdgaze::try_blend_dlb(inputs, negative, out) == CG_STATUS_INVALID_ARGUMENT);

    const float f = 800.0f;
    const std::array<float, 12> p{f, 0.0f, 0.0f, -f * 4.0f, 0.0f, f,    0.0f,
                                  -f * 1.6f, 0.0f, 0.0f, 1.0f, -1.0f};
    const cg_vec3 centre = crowdgaze::camera_center_from_projection(p);
    std::printf("camera centre: (%.3f, %.3f, %.3f)\n", static_cast<double>(centre.x),
                static_cast<double>(centre.y), static_cast<double>(centre.z));
    CHECK(std::fabs(centre.x - 4.0f) < 1e-3f && std::fabs(centre.y - 1.6f) < 1e-3f &&
          std::fabs(centre.z - 1.0f) < 1e-3f);
}

// Two keys (head turned 0 and 60 degrees) with a camera each; a viewer half-way.
void view_blender() {
    constexpr std::uint32_t kJoints = 2;  // neck, head
    crowdgaze::ViewBlender blender(crowdgaze::view_blender_config(kJoints, 2));
    CHECK(blender.joint_count() == kJoints && blender.key_count() == 2);
    for (std::uint32_t key = 0; key < 2; key++) {
        const float yaw = 60.0f * kDegree * static_cast<float>(key);
        // A one-second clip of 10 frames whose head nods; the neck stays put.
        std::vector<cg_dualquat> frames;
        for (int f = 0; f < 10; f++) {
            const float nod = 4.0f * kDegree * std::sin(2.0f * kPi * static_cast<float>(f) / 10.0f);
            frames.push_back(crowdgaze::dualquat_from_rt(yaw_quat(0.0f), {0.0f, 1.5f, 0.0f}));
            frames.push_back(crowdgaze::dualquat_from_rt(
                multiply(yaw_quat(yaw), cg_quat{std::sin(nod / 2), 0.0f, 0.0f, std::cos(nod / 2)}),
                {0.0f, 0.2f, 0.0f}));
        }
        blender.set_key_clip(key, frames, 10.0f, true);
        blender.add_camera({std::sin(yaw), 0.0f, std::cos(yaw)}, key);
    }
    const cg_dualquat character = crowdgaze::dualquat_from_rt(yaw_quat(0.0f), {5.0f, 0.0f, 0.0f});

    const std::vector<float> on_key = blender.weights(character, {5.0f + 3.0f * std::sin(60.0f * kDegree), 0.0f,
                                                                  3.0f * std::cos(60.0f * kDegree)});
    CHECK(on_key.size() == 2 && on_key[0] == 0.0f && on_key[1] == 1.0f);

    const cg_vec3 halfway{5.0f + 4.0f * std::sin(30.0f * kDegree), 0.0f, 4.0f * std::cos(30.0f * kDegree)};
    std::array<float, 2> weights{};
    blender.weights(character, halfway, weights);
    std::array<cg_dualquat, kJoints> pose{};
    CHECK(blender.evaluate(character, halfway, 0.0, pose));  // t = 0: no nod
    std::printf("half-way viewer: weights %.3f %.3f, head yaw %.2f deg\n",
                static_cast<double>(weights[0]), static_cast<double>(weights[1]),
                static_cast<double>(yaw_of(pose[1].real)));
    CHECK(std::fabs(weights[0] - 0.5f) < 1e-4f && std::fabs(weights[1] - 0.5f) < 1e-4f);
    CHECK(std::fabs(yaw_of(pose[1].real) - 30.0f) < 0.05f);

    // A static pose replaces key 1; errors; moves.
    std::array<cg_dualquat, kJoints> still{
        crowdgaze::dualquat_from_rt(yaw_quat(0.0f), {0.0f, 1.5f, 0.0f}),
        crowdgaze::dualquat_from_rt(yaw_quat(-20.0f * kDegree), {0.0f, 0.2f, 0.0f})};
    blender.set_key_pose(1, still);
    CHECK(blender.try_set_key_pose(2, still) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(blender.try_add_camera({0.0f, 0.0f, 0.0f}, 0) == CG_STATUS_INVALID_ARGUMENT);
    const cg_vec3 centre{5.0f, 0.0f, 0.0f};
    CHECK(blender.try_evaluate(character, centre, 0.0, pose) == CG_STATUS_INVALID_ARGUMENT);
    CHECK(blender.try_set_key_clip(0, {still.data(), 1}, 10.0f, true) == CG_STATUS_INVALID_ARGUMENT);

    crowdgaze::ViewBlender other;
    other = std::move(blender);
    CHECK(!blender && other && other.key_count() == 2);  // NOLINT: use after move on purpose
    CHECK(blender.key_count() == 0 && blender.joint_count() == 0);  // NOLINT: as above
    crowdgaze::ViewBlender third(std::move(other));
    CHECK(!other && other.key_count() == 0 && third.key_count() == 2);  // NOLINT: as above
    CHECK(third.evaluate(character, halfway, 0.25, pose));
    cg_view_blender* raw = third.release();
    CHECK(!third && third.joint_count() == 0);
    other.reset(raw, kJoints, 2);
    CHECK(other.raw() == raw && other.key_count() == 2);
    CHECK(other.evaluate(character, halfway, 0.25, pose));

    bool thrown = false;
    try {
        crowdgaze::ViewBlender bad(crowdgaze::view_blender_config(0, 2));
    } catch (const crowdgaze::Error& error) {
        thrown = error.status() == CG_STATUS_INVALID_ARGUMENT && !error.message().empty();
    }
    CHECK(thrown);
}

}  // namespace

int main() {
    std::printf("C++ wrapper over crowdgaze %s\n", crowdgaze::version_string());
    CHECK(crowdgaze::version_matches_header());
    try {
        crowd_gaze();
        eyelids();
        conversation();
        street_following();
        offline_plan();
        dual_quaternions();
        view_blender();
        const cg_chain_desc chain = crowdgaze::chain_desc_human(CG_AXIS_POSITIVE_Z, CG_AXIS_POSITIVE_X);
        CHECK(chain.joint_count == 10);
        cg_chain_desc bad{};
        CHECK(crowdgaze::try_chain_desc_human(CG_AXIS_POSITIVE_Z, CG_AXIS_NEGATIVE_Z, bad) ==
              CG_STATUS_INVALID_ARGUMENT);
    } catch (const crowdgaze::Error& error) {
        std::fprintf(stderr, "unexpected crowdgaze error: %s\n", error.what());
        return 1;
    }
    if (failures != 0) {
        std::fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    std::printf("ok\n");
    return 0;
}
