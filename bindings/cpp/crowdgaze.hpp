// crowdgaze.hpp — header-only C++17 wrapper of the crowdgaze C API (include/crowdgaze.h).
//
// - `crowdgaze::Crowd`, `crowdgaze::ViewBlender` and `crowdgaze::Rig` own a `cg_crowd*` /
//   `cg_view_blender*` / `cg_rig*` through one template, `crowdgaze::Owner`: move-only, the
//   destructor calls the matching `_destroy`; `raw()` lends the handle, `release()` gives
//   it up.
// - Every call exists twice: `name(...)` throws `crowdgaze::Error` (the status and the
//   library's `cg_last_error_message`), `try_name(...)` is `noexcept` and returns the
//   `cg_status` (`[[nodiscard]]`). The wrapper allocates nothing in either, except where a
//   function returns a `std::vector` or `std::string` (said on each). Built without
//   exceptions (-fno-exceptions), the throwing forms abort with the message on an error:
//   use the `try_` forms.
// - Bulk calls take `crowdgaze::Span<T>`: a pointer and a count, built implicitly from a
//   `std::vector`, a `std::array`, a C array, or `{pointer, count}`. Nothing is copied.
// - The plain C structs (`cg_vec3`, `cg_quat`, `cg_entity_state`, ...) are used as they are.
//
// Thread safety is the C API's: a handle is not safe for concurrent mutation; `const`
// member functions may run concurrently with each other.
#ifndef CROWDGAZE_HPP
#define CROWDGAZE_HPP

#include "crowdgaze.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace crowdgaze {

// ---------------------------------------------------------------------------------------
// Span: a pointer and a count (C++17 has no std::span).

template <class T>
class Span {
   public:
    using element_type = T;
    using value_type = std::remove_cv_t<T>;

    constexpr Span() noexcept = default;
    constexpr Span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}

    // Any contiguous container with data() and size() whose elements convert: std::vector,
    // std::array, C arrays, std::string, another Span (Span<T> to Span<const T>).
    template <class Container,
              class Pointer = decltype(std::data(std::declval<Container&>())),
              class = std::enable_if_t<
                  !std::is_same_v<std::remove_cv_t<std::remove_reference_t<Container>>, Span> &&
                  std::is_convertible_v<Pointer, T*> &&
                  std::is_same_v<std::remove_cv_t<std::remove_pointer_t<Pointer>>, value_type>>>
    constexpr Span(Container&& container) noexcept  // NOLINT: implicit on purpose
        : data_(std::data(container)), size_(std::size(container)) {}

    constexpr T* data() const noexcept { return data_; }
    constexpr std::size_t size() const noexcept { return size_; }
    constexpr bool empty() const noexcept { return size_ == 0; }
    constexpr T* begin() const noexcept { return data_; }
    constexpr T* end() const noexcept { return data_ + size_; }
    constexpr T& operator[](std::size_t i) const noexcept { return data_[i]; }
    // Elements `offset .. offset + count` (the caller keeps them in range).
    constexpr Span subspan(std::size_t offset, std::size_t count) const noexcept {
        return Span(data_ + offset, count);
    }

   private:
    T* data_ = nullptr;
    std::size_t size_ = 0;
};

// ---------------------------------------------------------------------------------------
// Errors.

// The calling thread's last error message (allocates the string).
inline std::string last_error_message() {
    std::size_t length = cg_last_error_message(nullptr, 0);
    std::vector<char> buffer(length + 1, '\0');
    cg_last_error_message(buffer.data(), buffer.size());
    return std::string(buffer.data(), length);
}

// The static description of a status ("null argument", ...).
inline const char* status_string(cg_status status) noexcept {
    return cg_status_str(static_cast<std::uint32_t>(status));
}

// A failed crowdgaze call: the status and the one-line message of `cg_last_error_message`
// (which starts with the kind of error, e.g. "invalid argument: dt is -1, must be >= 0").
// `what()` is that message, or the status description if the message is empty.
class Error : public std::runtime_error {
   public:
    Error(cg_status status, const std::string& message)
        : std::runtime_error(message.empty() ? std::string(status_string(status)) : message),
          status_(status),
          message_(message) {}

    cg_status status() const noexcept { return status_; }
    // The library's message (empty if it gave none).
    const std::string& message() const noexcept { return message_; }

   private:
    cg_status status_;
    std::string message_;
};

namespace detail {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS) || defined(_CPPUNWIND)
[[noreturn]] inline void fail(const Error& error) { throw error; }
#else
[[noreturn]] inline void fail(const Error& error) {
    std::fprintf(stderr, "crowdgaze: %s\n", error.what());
    std::abort();
}
#endif
}  // namespace detail

// Throws `Error` with the thread's last error message unless `status` is `CG_STATUS_OK`.
// Built without exceptions (-fno-exceptions, as Unreal modules are by default), it prints
// the message to stderr and aborts instead: use the `try_` forms there.
inline void check(cg_status status) {
    if (status != CG_STATUS_OK) {
        detail::fail(Error(status, last_error_message()));
    }
}

// Like `check`, but `CG_STATUS_NOT_CONVERGED` (outputs written, best iterate) is not an
// error: returns true if converged, false if not.
inline bool check_converged(cg_status status) {
    if (status == CG_STATUS_NOT_CONVERGED) {
        return false;
    }
    check(status);
    return true;
}

namespace detail {
// Sizes the wrapper checks itself (the C call takes one count for two arrays) report this
// status without a library message; the exception's message says what did not match.
inline void check_sizes(bool good, const char* what) {
    if (!good) {
        fail(Error(CG_STATUS_INVALID_ARGUMENT, what));
    }
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Version.

// The linked library's version, `(major << 16) | (minor << 8) | patch`.
inline std::uint32_t version() noexcept { return cg_version(); }
// The linked library's version string, "major.minor.patch" (static).
inline const char* version_string() noexcept { return cg_version_string(); }
// Whether the linked library's major version (and, before 1.0, minor) is the header's.
inline bool version_matches_header() noexcept {
    const std::uint32_t v = cg_version();
    const std::uint32_t major = v >> 16, minor = (v >> 8) & 0xff;
    return major == CG_VERSION_MAJOR && (CG_VERSION_MAJOR != 0 || minor == CG_VERSION_MINOR);
}

// ---------------------------------------------------------------------------------------
// Plain structs filled with their defaults (the C `_init` functions; they cannot fail on a
// valid pointer to a struct whose `struct_size` is set).

// A versioned struct (one that starts with `uint32_t struct_size`) zeroed, with its
// `struct_size` set to `sizeof(T)`, as every call taking it requires before the call.
template <typename T>
inline T sized() noexcept {
    T value{};
    value.struct_size = static_cast<std::uint32_t>(sizeof(T));
    return value;
}

inline cg_crowd_config crowd_config() noexcept {
    cg_crowd_config config = sized<cg_crowd_config>();
    (void)cg_crowd_config_init(&config);
    return config;
}
// The street preset (`cg_crowd_config_init_street`): the defaults, but `max_distance` 17 m
// and gaze following on (`follow_enabled` 1). Give the characters
// `CG_ATTENTION_MODEL_STREET`. In metres, like `crowd_config()`: with another
// `units_per_metre`, scale the length fields too.
inline cg_crowd_config street_config() noexcept {
    cg_crowd_config config = sized<cg_crowd_config>();
    (void)cg_crowd_config_init_street(&config);
    return config;
}
inline cg_character_desc character_desc() noexcept {
    cg_character_desc desc = sized<cg_character_desc>();
    (void)cg_character_desc_init(&desc);
    return desc;
}
inline cg_character_desc character_desc(cg_vec3 position, float heading = 0.0f) noexcept {
    cg_character_desc desc = character_desc();
    desc.position = position;
    desc.heading = heading;
    return desc;
}
inline cg_object_desc object_desc() noexcept {
    cg_object_desc desc = sized<cg_object_desc>();
    (void)cg_object_desc_init(&desc);
    return desc;
}
inline cg_entity_state entity_state() noexcept {
    cg_entity_state state = sized<cg_entity_state>();
    (void)cg_entity_state_init(&state);
    return state;
}
// A state for entity `id` at `position`, heading from motion (the usual walker).
inline cg_entity_state entity_state(std::uint32_t id, cg_vec3 position) noexcept {
    cg_entity_state state = entity_state();
    state.id = id;
    state.position = position;
    state.flags = CG_STATE_HEADING_FROM_MOTION;
    return state;
}
inline cg_gaze_target gaze_target() noexcept {
    cg_gaze_target target = sized<cg_gaze_target>();
    (void)cg_gaze_target_init(&target);
    return target;
}
// A point target (default priority: override).
inline cg_gaze_target gaze_target_point(cg_vec3 point,
                                        std::uint32_t priority = CG_GAZE_PRIORITY_OVERRIDE) noexcept {
    cg_gaze_target target = gaze_target();
    target.kind = CG_GAZE_TARGET_POINT;
    target.point = point;
    target.priority = priority;
    return target;
}
// An entity target, followed as it moves.
inline cg_gaze_target gaze_target_entity(std::uint32_t entity,
                                         std::uint32_t priority = CG_GAZE_PRIORITY_OVERRIDE) noexcept {
    cg_gaze_target target = gaze_target();
    target.kind = CG_GAZE_TARGET_ENTITY;
    target.entity = entity;
    target.priority = priority;
    return target;
}
inline cg_view_blender_config view_blender_config() noexcept {
    cg_view_blender_config config = sized<cg_view_blender_config>();
    (void)cg_view_blender_config_init(&config);
    return config;
}
inline cg_view_blender_config view_blender_config(std::uint32_t joint_count,
                                                  std::uint32_t key_count,
                                                  cg_blend_method method = CG_BLEND_METHOD_DLB) noexcept {
    cg_view_blender_config config = view_blender_config();
    config.joint_count = joint_count;
    config.key_count = key_count;
    config.method = static_cast<std::uint32_t>(method);
    return config;
}

// The human gaze chain (5 spine, 2 cervical, head, 2 eyes; metres) for these axes.
// `out` is written (`struct_size` set) only on success.
[[nodiscard]] inline cg_status try_chain_desc_human(cg_axis up, cg_axis forward,
                                                    cg_chain_desc& out) noexcept {
    cg_chain_desc desc = sized<cg_chain_desc>();
    const cg_status status = cg_chain_desc_init_human(&desc, static_cast<std::uint32_t>(up),
                                                      static_cast<std::uint32_t>(forward));
    if (status == CG_STATUS_OK) {
        out = desc;
    }
    return status;
}
inline cg_chain_desc chain_desc_human(cg_axis up, cg_axis forward) {
    cg_chain_desc desc{};
    check(try_chain_desc_human(up, forward, desc));
    return desc;
}

// ---------------------------------------------------------------------------------------
// Handle owners.

// Owns one C handle `T*` and frees it with `Destroy` (which accepts NULL): move-only.
// `Crowd` and `ViewBlender` are owners of `cg_crowd` and `cg_view_blender`.
template <class T, void (*Destroy)(T*)>
class Owner {
   public:
    // An empty owner; `operator bool` is false.
    Owner() noexcept = default;
    // Takes ownership of `adopted` (NULL gives an empty owner).
    explicit Owner(T* adopted) noexcept : handle_(adopted) {}
    ~Owner() { Destroy(handle_); }
    Owner(const Owner&) = delete;
    Owner& operator=(const Owner&) = delete;
    Owner(Owner&& other) noexcept : handle_(other.release()) {}
    Owner& operator=(Owner&& other) noexcept {
        if (this != &other) {
            reset(other.release());
        }
        return *this;
    }

    // The handle, still owned by this object.
    T* raw() const noexcept { return handle_; }
    // Gives up ownership: the caller must free the returned handle.
    [[nodiscard]] T* release() noexcept { return std::exchange(handle_, nullptr); }
    // Frees the handle held (if any) and takes `adopted`.
    void reset(T* adopted = nullptr) noexcept { Destroy(std::exchange(handle_, adopted)); }
    explicit operator bool() const noexcept { return handle_ != nullptr; }

   private:
    T* handle_ = nullptr;
};

// ---------------------------------------------------------------------------------------
// Crowd.

// Owns a `cg_crowd*`: attention and gaze IK for a crowd of characters. Move-only.
class Crowd : public Owner<cg_crowd, cg_crowd_destroy> {
   public:
    // An empty owner (no crowd); `operator bool` is false.
    Crowd() noexcept = default;
    // Creates a crowd from `config` (see `crowd_config()`); throws `Error`.
    explicit Crowd(const cg_crowd_config& config) { check(try_create(config, *this)); }
    // Takes ownership of a crowd created elsewhere (NULL gives an empty owner).
    explicit Crowd(cg_crowd* adopted) noexcept : Owner(adopted) {}

    // Creates a crowd into `out` (replacing what it held) without throwing.
    [[nodiscard]] static cg_status try_create(const cg_crowd_config& config, Crowd& out) noexcept {
        cg_crowd* created = nullptr;
        const cg_status status = cg_crowd_create(&config, &created);
        if (status == CG_STATUS_OK) {
            out.reset(created);
        }
        return status;
    }

    // --- setup -------------------------------------------------------------------------

    // `out` is written (`struct_size` set) only on success.
    [[nodiscard]] cg_status try_config(cg_crowd_config& out) const noexcept {
        cg_crowd_config config = sized<cg_crowd_config>();
        const cg_status status = cg_crowd_get_config(raw(), &config);
        if (status == CG_STATUS_OK) {
            out = config;
        }
        return status;
    }
    cg_crowd_config config() const {
        cg_crowd_config out{};
        check(try_config(out));
        return out;
    }

    [[nodiscard]] cg_status try_add_character(const cg_character_desc& desc,
                                              std::uint32_t& out_id) noexcept {
        return cg_crowd_add_character(raw(), &desc, &out_id);
    }
    std::uint32_t add_character(const cg_character_desc& desc) {
        std::uint32_t id = CG_NO_TARGET;
        check(try_add_character(desc, id));
        return id;
    }
    std::uint32_t add_character_at(cg_vec3 position, float heading = 0.0f) {
        return add_character(character_desc(position, heading));
    }

    [[nodiscard]] cg_status try_add_object(const cg_object_desc& desc,
                                           std::uint32_t& out_id) noexcept {
        return cg_crowd_add_object(raw(), &desc, &out_id);
    }
    std::uint32_t add_object(const cg_object_desc& desc) {
        std::uint32_t id = CG_NO_TARGET;
        check(try_add_object(desc, id));
        return id;
    }

    [[nodiscard]] cg_status try_remove_entity(std::uint32_t id) noexcept {
        return cg_crowd_remove_entity(raw(), id);
    }
    void remove_entity(std::uint32_t id) { check(try_remove_entity(id)); }

    [[nodiscard]] cg_status try_character_count(std::size_t& out) const noexcept {
        return cg_crowd_character_count(raw(), &out);
    }
    std::size_t character_count() const {
        std::size_t count = 0;
        check(try_character_count(count));
        return count;
    }

    // `out` is written (`struct_size` set) only on success.
    [[nodiscard]] cg_status try_character_params(std::uint32_t character,
                                                 cg_character_params& out) const noexcept {
        cg_character_params params = sized<cg_character_params>();
        const cg_status status = cg_crowd_get_character_params(raw(), character, &params);
        if (status == CG_STATUS_OK) {
            out = params;
        }
        return status;
    }
    cg_character_params character_params(std::uint32_t character) const {
        cg_character_params params{};
        check(try_character_params(character, params));
        return params;
    }
    [[nodiscard]] cg_status try_set_character_params(std::uint32_t character,
                                                     const cg_character_params& params) noexcept {
        return cg_crowd_set_character_params(raw(), character, &params);
    }
    void set_character_params(std::uint32_t character, const cg_character_params& params) {
        check(try_set_character_params(character, params));
    }

    // Adds the viewer as an entity characters may look at (first call; returns its id) or
    // moves it (later calls).
    [[nodiscard]] cg_status try_set_viewer(const cg_vec3& position, float impact,
                                           std::uint32_t& out_id) noexcept {
        return cg_crowd_set_viewer(raw(), &position, impact, &out_id);
    }
    std::uint32_t set_viewer(const cg_vec3& position, float impact = 1.0f) {
        std::uint32_t id = CG_NO_TARGET;
        check(try_set_viewer(position, impact, id));
        return id;
    }

    // Attention every `period` steps for this character (0: the crowd's level of detail).
    [[nodiscard]] cg_status try_set_attention_period(std::uint32_t character,
                                                     std::uint32_t period) noexcept {
        return cg_crowd_set_attention_period(raw(), character, period);
    }
    void set_attention_period(std::uint32_t character, std::uint32_t period) {
        check(try_set_attention_period(character, period));
    }

    [[nodiscard]] cg_status try_set_impact(std::uint32_t entity, float impact) noexcept {
        return cg_crowd_set_impact(raw(), entity, impact);
    }
    void set_impact(std::uint32_t entity, float impact) { check(try_set_impact(entity, impact)); }

    // --- every frame -------------------------------------------------------------------

    // Pushes the states of (some of) the entities at time `t`; see cg_crowd_push_frame.
    [[nodiscard]] cg_status try_push_frame(double t, Span<const cg_entity_state> states) noexcept {
        return cg_crowd_push_frame(raw(), t, states.data(), states.size());
    }
    void push_frame(double t, Span<const cg_entity_state> states) {
        check(try_push_frame(t, states));
    }

    // A frame pushed in parts from several threads: begin_push once, push_range from any
    // number of threads (each entity in one part only), end_push after they all returned.
    // The same as one push_frame of all the parts. See cg_crowd_begin_push,
    // cg_crowd_push_range and cg_crowd_end_push.
    [[nodiscard]] cg_status try_begin_push(double t) noexcept {
        return cg_crowd_begin_push(raw(), t);
    }
    void begin_push(double t) { check(try_begin_push(t)); }
    [[nodiscard]] cg_status try_push_range(Span<const cg_entity_state> states) noexcept {
        return cg_crowd_push_range(raw(), states.data(), states.size());
    }
    void push_range(Span<const cg_entity_state> states) { check(try_push_range(states)); }
    [[nodiscard]] cg_status try_end_push() noexcept { return cg_crowd_end_push(raw()); }
    void end_push() { check(try_end_push()); }

    // Attention and gaze IK for every character, `dt` seconds after the previous step.
    [[nodiscard]] cg_status try_step(float dt) noexcept { return cg_crowd_step(raw(), dt); }
    void step(float dt) { check(try_step(dt)); }

    // A step split into ranges for your job system: begin_step once, step_range from any
    // number of threads on disjoint ranges (of the storage order, not read_gaze's order:
    // split 0 .. character_count() any way), end_step after they all returned. See
    // cg_crowd_begin_step, cg_crowd_step_range and cg_crowd_end_step.
    [[nodiscard]] cg_status try_begin_step(float dt) noexcept {
        return cg_crowd_begin_step(raw(), dt);
    }
    void begin_step(float dt) { check(try_begin_step(dt)); }
    [[nodiscard]] cg_status try_step_range(std::uint32_t first, std::uint32_t count) noexcept {
        return cg_crowd_step_range(raw(), first, count);
    }
    void step_range(std::uint32_t first, std::uint32_t count) {
        check(try_step_range(first, count));
    }
    [[nodiscard]] cg_status try_end_step() noexcept { return cg_crowd_end_step(raw()); }
    void end_step() { check(try_end_step()); }

    // Where the characters look, in character order; returns how many were written.
    [[nodiscard]] cg_status try_read_gaze(Span<cg_gaze_info> out,
                                          std::size_t& written) const noexcept {
        return cg_crowd_read_gaze(raw(), out.data(), out.size(), &written);
    }
    std::size_t read_gaze(Span<cg_gaze_info> out) const {
        std::size_t written = 0;
        check(try_read_gaze(out, written));
        return written;
    }

    // Joints of characters `first .. first + count` together (what read_joints needs).
    [[nodiscard]] cg_status try_joint_total(std::uint32_t first, std::uint32_t count,
                                            std::size_t& out) const noexcept {
        return cg_crowd_joint_total(raw(), first, count, &out);
    }
    std::size_t joint_total(std::uint32_t first, std::uint32_t count) const {
        std::size_t total = 0;
        check(try_joint_total(first, count, total));
        return total;
    }

    // Final local rotations (base * delta) of the chain joints of characters
    // `first .. first + count`, bottom to top, chain after chain.
    [[nodiscard]] cg_status try_read_joints(std::uint32_t first, std::uint32_t count,
                                            Span<cg_quat> out) const noexcept {
        return cg_crowd_read_joints(raw(), first, count, out.data(), out.size());
    }
    void read_joints(std::uint32_t first, std::uint32_t count, Span<cg_quat> out) const {
        check(try_read_joints(first, count, out));
    }

    // The gaze's delta rotations alone (final = base * delta).
    [[nodiscard]] cg_status try_read_joint_deltas(std::uint32_t first, std::uint32_t count,
                                                  Span<cg_quat> out) const noexcept {
        return cg_crowd_read_joint_deltas(raw(), first, count, out.data(), out.size());
    }
    void read_joint_deltas(std::uint32_t first, std::uint32_t count, Span<cg_quat> out) const {
        check(try_read_joint_deltas(first, count, out));
    }

    // Eye positions and directions of characters `first .. first + count` (debug drawing).
    [[nodiscard]] cg_status try_read_eyes(std::uint32_t first, std::uint32_t count,
                                          Span<cg_eye_info> out) const noexcept {
        return cg_crowd_read_eyes(raw(), first, count, out.data(), out.size());
    }
    void read_eyes(std::uint32_t first, std::uint32_t count, Span<cg_eye_info> out) const {
        check(try_read_eyes(first, count, out));
    }

    // Eyelids of characters `first .. first + count`: each eye's blink closure (0 open,
    // 1 closed) and upper lid pitch following the eye. `out.size()` must be at least `count`.
    [[nodiscard]] cg_status try_read_eyelids(std::uint32_t first, std::uint32_t count,
                                             Span<cg_eyelids> out) const noexcept {
        return cg_crowd_read_eyelids(raw(), first, count, out.data(), out.size());
    }
    void read_eyelids(std::uint32_t first, std::uint32_t count, Span<cg_eyelids> out) const {
        check(try_read_eyelids(first, count, out));
    }

    // The animated base pose of one character's chain joints (local rotations, bottom to
    // top), before step.
    [[nodiscard]] cg_status try_set_base_pose(std::uint32_t character,
                                              Span<const cg_quat> local) noexcept {
        return cg_crowd_set_base_pose(raw(), character, local.data(), local.size());
    }
    void set_base_pose(std::uint32_t character, Span<const cg_quat> local) {
        check(try_set_base_pose(character, local));
    }

    // Base poses of many characters: their joints packed in the order of `characters`.
    [[nodiscard]] cg_status try_set_base_poses(Span<const std::uint32_t> characters,
                                               Span<const cg_quat> local) noexcept {
        return cg_crowd_set_base_poses(raw(), characters.data(), characters.size(),
                                       local.data(), local.size());
    }
    void set_base_poses(Span<const std::uint32_t> characters, Span<const cg_quat> local) {
        check(try_set_base_poses(characters, local));
    }

    // Explicit (top-down) gaze targets.
    [[nodiscard]] cg_status try_set_gaze_target(std::uint32_t character,
                                                const cg_gaze_target& target) noexcept {
        return cg_crowd_set_gaze_target(raw(), character, &target);
    }
    void set_gaze_target(std::uint32_t character, const cg_gaze_target& target) {
        check(try_set_gaze_target(character, target));
    }
    void look_at(std::uint32_t character, cg_vec3 point) {
        set_gaze_target(character, gaze_target_point(point));
    }
    [[nodiscard]] cg_status try_clear_gaze_target(std::uint32_t character) noexcept {
        return cg_crowd_clear_gaze_target(raw(), character);
    }
    void clear_gaze_target(std::uint32_t character) { check(try_clear_gaze_target(character)); }

    // --- conversations -----------------------------------------------------------------

    // Makes `members` (2 to CG_MAX_CONVERSATION_MEMBERS character ids, each in no other
    // conversation) a group standing together and talking; its id goes to `out_group` (only
    // on success). Who talks comes with each pushed state (`CG_STATE_TALKING` in `flags`).
    [[nodiscard]] cg_status try_set_conversation(Span<const std::uint32_t> members,
                                                 std::uint32_t& out_group) noexcept {
        return cg_crowd_set_conversation(raw(), members.data(), members.size(), &out_group);
    }
    std::uint32_t set_conversation(Span<const std::uint32_t> members) {
        std::uint32_t group = CG_NO_TARGET;
        check(try_set_conversation(members, group));
        return group;
    }
    // Ends conversation `group`: its members go back to their own attention. (A group also
    // ends when removing its members leaves it one.)
    [[nodiscard]] cg_status try_remove_conversation(std::uint32_t group) noexcept {
        return cg_crowd_remove_conversation(raw(), group);
    }
    void remove_conversation(std::uint32_t group) { check(try_remove_conversation(group)); }
    // The conversation `character` is in, or `CG_NO_TARGET` if it is in none.
    [[nodiscard]] cg_status try_conversation(std::uint32_t character,
                                             std::uint32_t& out_group) const noexcept {
        return cg_crowd_get_conversation(raw(), character, &out_group);
    }
    std::uint32_t conversation(std::uint32_t character) const {
        std::uint32_t group = CG_NO_TARGET;
        check(try_conversation(character, group));
        return group;
    }

    // --- gaze following ----------------------------------------------------------------

    // What `cg_crowd_read_following` says of a character: whether it glances now where
    // others stare, at `point` (world, your units; the origin when not following), and
    // how many such glances it has started.
    struct Following {
        bool following = false;
        cg_vec3 point{};
        std::uint32_t glances = 0;
    };
    // `character`'s gaze following (the `follow_*` fields of the config); `out` is written
    // only on success.
    [[nodiscard]] cg_status try_following(std::uint32_t character,
                                          Following& out) const noexcept {
        cg_vec3 point{};
        std::uint32_t following = 0, glances = 0;
        const cg_status status =
            cg_crowd_read_following(raw(), character, &point, &following, &glances);
        if (status == CG_STATUS_OK) {
            out.following = following != 0;
            out.point = point;
            out.glances = glances;
        }
        return status;
    }
    Following following(std::uint32_t character) const {
        Following out;
        check(try_following(character, out));
        return out;
    }

    // --- tools and offline planning ----------------------------------------------------

    [[nodiscard]] cg_status try_score(std::uint32_t character, std::uint32_t entity,
                                      cg_score_breakdown& out) const noexcept {
        return cg_crowd_score(raw(), character, entity, &out);
    }
    cg_score_breakdown score(std::uint32_t character, std::uint32_t entity) const {
        cg_score_breakdown out{};
        check(try_score(character, entity, out));
        return out;
    }

    [[nodiscard]] cg_status try_plan() noexcept { return cg_crowd_plan(raw()); }
    void plan() { check(try_plan()); }
    [[nodiscard]] cg_status try_clear_plan() noexcept { return cg_crowd_clear_plan(raw()); }
    void clear_plan() { check(try_clear_plan()); }

    // Fills `out` with the first planned constraints of `character` and writes how many
    // there are in all to `total`.
    [[nodiscard]] cg_status try_read_constraints(std::uint32_t character, Span<cg_constraint> out,
                                                 std::size_t& total) const noexcept {
        return cg_crowd_read_constraints(raw(), character, out.data(), out.size(), &total);
    }
    std::size_t read_constraints(std::uint32_t character, Span<cg_constraint> out) const {
        std::size_t total = 0;
        check(try_read_constraints(character, out, total));
        return total;
    }
    // All of a character's planned constraints (allocates the vector).
    std::vector<cg_constraint> constraints(std::uint32_t character) const {
        std::vector<cg_constraint> out(read_constraints(character, {}));
        const std::size_t total = read_constraints(character, out);
        out.resize(total < out.size() ? total : out.size());
        return out;
    }

};

// ---------------------------------------------------------------------------------------
// Rig: your skeleton mapped to a gaze chain.

// A `cg_rig_desc` with its defaults (up and forward detected, metres, no bone map, the
// crowd Y up, +Z forward, metres). Set `bone_count` and the bone arrays (they have no
// default), then what differs.
inline cg_rig_desc rig_desc() noexcept {
    cg_rig_desc desc = sized<cg_rig_desc>();
    (void)cg_rig_desc_init(&desc);
    return desc;
}
// Copies the crowd's axes and units (`up_axis`, `forward_axis`, `units_per_metre` of
// `config`) into `desc`: the chain and the poses are then in that crowd's axes and units.
inline void set_rig_crowd(cg_rig_desc& desc, const cg_crowd_config& config) noexcept {
    desc.crowd_up = config.up_axis;
    desc.crowd_forward = config.forward_axis;
    desc.crowd_units_per_metre = config.units_per_metre;
}

// Owns a `cg_rig*`: a skeleton mapped to a gaze chain (which bones are spine, neck, head
// and eyes, found by name, `bone_map` overriding), immutable once created: every `const`
// member function may run on several threads at once. Move-only.
//
// Each frame: `base_pose(bone_rotations, base)` then `Crowd::set_base_pose(id, base)`;
// after the step, `Crowd::read_joints(row, 1, joints)` then
// `write_joints(joints, bone_rotations)`.
class Rig : public Owner<cg_rig, cg_rig_destroy> {
   public:
    // An empty owner (no rig); `operator bool` is false.
    Rig() noexcept = default;
    // Maps the skeleton `desc` describes (see `rig_desc()`); throws `Error`, whose message
    // names the bone and the `bone_map` entry that fixes a skeleton that does not map.
    explicit Rig(const cg_rig_desc& desc) { check(try_create(desc, *this)); }
    // Maps a skeleton in one call: one name, parent (-1: none; parents before children) and
    // rest translation (relative to the parent, `units_per_metre` units to the metre) per
    // bone; `bone_map` ("Name=role,...") overrides roles (nullptr: none); `crowd` (nullptr:
    // Y up, +Z forward, metres) gives the crowd's axes and units; `rotations` the rest
    // rotations (empty: identity). Up and forward are detected. Throws `Error`.
    Rig(Span<const char* const> names, Span<const std::int32_t> parents,
        Span<const cg_vec3> translations, float units_per_metre = 1.0f,
        const char* bone_map = nullptr, const cg_crowd_config* crowd = nullptr,
        Span<const cg_quat> rotations = {}) {
        detail::check_sizes(sizes_match(names.size(), parents, translations, rotations),
                            "crowdgaze::Rig: names, parents, translations and rotations "
                            "(if given) differ in size");
        check(try_create(names, parents, translations, units_per_metre, bone_map, crowd,
                         rotations, *this));
    }
    // The same with `std::string` names (allocates a vector of pointers to them). A name
    // holding a NUL character is refused (`CG_STATUS_INVALID_ARGUMENT`).
    Rig(const std::vector<std::string>& names, Span<const std::int32_t> parents,
        Span<const cg_vec3> translations, float units_per_metre = 1.0f,
        const std::string& bone_map = std::string(), const cg_crowd_config* crowd = nullptr,
        Span<const cg_quat> rotations = {}) {
        detail::check_sizes(sizes_match(names.size(), parents, translations, rotations),
                            "crowdgaze::Rig: names, parents, translations and rotations "
                            "(if given) differ in size");
        detail::check_sizes(no_nul(names, bone_map),
                            "crowdgaze::Rig: a name or the bone map holds a NUL character");
        check(try_create(names, parents, translations, units_per_metre, bone_map, crowd,
                         rotations, *this));
    }
    // Takes ownership of a rig created elsewhere (NULL gives an empty owner).
    explicit Rig(cg_rig* adopted) noexcept : Owner(adopted) {}

    // Creates a rig into `out` (replacing what it held) without throwing.
    [[nodiscard]] static cg_status try_create(const cg_rig_desc& desc, Rig& out) noexcept {
        cg_rig* created = nullptr;
        const cg_status status = cg_rig_create(&desc, &created);
        if (status == CG_STATUS_OK) {
            out.reset(created);
        }
        return status;
    }
    // The one-call form without throwing: `CG_STATUS_INVALID_ARGUMENT` (and `out`
    // unchanged) if the sizes differ, else `cg_rig_create`'s status.
    [[nodiscard]] static cg_status try_create(Span<const char* const> names,
                                              Span<const std::int32_t> parents,
                                              Span<const cg_vec3> translations,
                                              float units_per_metre, const char* bone_map,
                                              const cg_crowd_config* crowd,
                                              Span<const cg_quat> rotations,
                                              Rig& out) noexcept {
        if (!sizes_match(names.size(), parents, translations, rotations)) {
            return CG_STATUS_INVALID_ARGUMENT;
        }
        cg_rig_desc desc = rig_desc();
        desc.bone_count = static_cast<std::uint32_t>(names.size());
        desc.bone_names = names.data();
        desc.parents = parents.data();
        desc.rest_translations = translations.data();
        desc.rest_rotations = rotations.empty() ? nullptr : rotations.data();
        desc.units_per_metre = units_per_metre;
        desc.bone_map = bone_map;
        if (crowd != nullptr) {
            set_rig_crowd(desc, *crowd);
        }
        return try_create(desc, out);
    }
    // With `std::string` names and bone map (empty: none). Allocates the pointer vector;
    // `CG_STATUS_OUT_OF_MEMORY` if that fails (built with exceptions),
    // `CG_STATUS_INVALID_ARGUMENT` for a NUL inside a name or the bone map.
    [[nodiscard]] static cg_status try_create(const std::vector<std::string>& names,
                                              Span<const std::int32_t> parents,
                                              Span<const cg_vec3> translations,
                                              float units_per_metre, const std::string& bone_map,
                                              const cg_crowd_config* crowd,
                                              Span<const cg_quat> rotations,
                                              Rig& out) noexcept {
        if (!sizes_match(names.size(), parents, translations, rotations) ||
            !no_nul(names, bone_map)) {
            return CG_STATUS_INVALID_ARGUMENT;
        }
        std::vector<const char*> pointers;
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS) || defined(_CPPUNWIND)
        try {
            pointers.reserve(names.size());
        } catch (...) {
            return CG_STATUS_OUT_OF_MEMORY;
        }
#else
        pointers.reserve(names.size());
#endif
        for (const std::string& name : names) {
            pointers.push_back(name.c_str());
        }
        return try_create(Span<const char* const>(pointers.data(), pointers.size()), parents,
                          translations, units_per_metre,
                          bone_map.empty() ? nullptr : bone_map.c_str(), crowd, rotations, out);
    }

    // --- what was mapped ---------------------------------------------------------------

    // The gaze chain (the crowd's axes and units), for `cg_character_desc.chain`. `out` is
    // written (`struct_size` set) only on success.
    [[nodiscard]] cg_status try_chain(cg_chain_desc& out) const noexcept {
        cg_chain_desc chain = sized<cg_chain_desc>();
        const cg_status status = cg_rig_chain(raw(), &chain);
        if (status == CG_STATUS_OK) {
            out = chain;
        }
        return status;
    }
    cg_chain_desc chain() const {
        cg_chain_desc out{};
        check(try_chain(out));
        return out;
    }

    // The number of bones (of `bone_rotations`).
    [[nodiscard]] cg_status try_bone_count(std::uint32_t& out) const noexcept {
        return cg_rig_bone_count(raw(), &out);
    }
    std::uint32_t bone_count() const {
        std::uint32_t count = 0;
        check(try_bone_count(count));
        return count;
    }
    // The number of chain joints (of a base pose, and of the joints read for the character).
    [[nodiscard]] cg_status try_joint_count(std::uint32_t& out) const noexcept {
        return cg_rig_joint_count(raw(), &out);
    }
    std::uint32_t joint_count() const {
        std::uint32_t count = 0;
        check(try_joint_count(count));
        return count;
    }

    // The bone of each chain joint, bottom to top (spine, neck, head, left and right eye
    // if any) into `out` (at least `joint_count()` elements).
    [[nodiscard]] cg_status try_chain_bones(Span<std::uint32_t> out) const noexcept {
        return cg_rig_chain_bones(raw(), out.data(), out.size());
    }
    // Allocates the vector.
    std::vector<std::uint32_t> chain_bones() const {
        std::vector<std::uint32_t> out(joint_count());
        check(try_chain_bones(out));
        return out;
    }

    // The role (`cg_bone_role` values) of every bone, the skeleton's order, into `out` (at
    // least `bone_count()` elements).
    [[nodiscard]] cg_status try_bone_roles(Span<std::uint32_t> out) const noexcept {
        return cg_rig_bone_roles(raw(), out.data(), out.size());
    }
    // Allocates the vector.
    std::vector<cg_bone_role> bone_roles() const {
        std::vector<std::uint32_t> values(bone_count());
        check(try_bone_roles(values));
        std::vector<cg_bone_role> out;
        out.reserve(values.size());
        for (const std::uint32_t value : values) {
            out.push_back(static_cast<cg_bone_role>(value));
        }
        return out;
    }

    // The mapping report (what the chain is, the axes and how they were found, the role of
    // each chain bone and why, notes), copied into `buffer` as `cg_rig_report` does;
    // returns its full length.
    std::size_t report(Span<char> buffer) const noexcept {
        return cg_rig_report(raw(), buffer.data(), buffer.size());
    }
    // Allocates the string (empty for an empty owner).
    std::string report() const {
        const std::size_t length = cg_rig_report(raw(), nullptr, 0);
        std::vector<char> buffer(length + 1, '\0');
        cg_rig_report(raw(), buffer.data(), buffer.size());
        return std::string(buffer.data(), length);
    }

    // --- each frame --------------------------------------------------------------------

    // The crowd's base pose (`joint_count()` rotations into `out_base`, at least that many;
    // for `Crowd::set_base_pose`) from your bone local rotations (`bone_count()` of them,
    // each relative to its parent, the skeleton's order). Allocates nothing.
    [[nodiscard]] cg_status try_base_pose(Span<const cg_quat> bone_rotations,
                                          Span<cg_quat> out_base) const noexcept {
        return cg_rig_base_pose(raw(), bone_rotations.data(), bone_rotations.size(),
                                out_base.data(), out_base.size());
    }
    void base_pose(Span<const cg_quat> bone_rotations, Span<cg_quat> out_base) const {
        check(try_base_pose(bone_rotations, out_base));
    }
    // Resizes `out` to `joint_count()` first (allocates only if it grows).
    void base_pose(const std::vector<cg_quat>& bone_rotations, std::vector<cg_quat>& out) const {
        out.resize(joint_count());
        base_pose(Span<const cg_quat>(bone_rotations), Span<cg_quat>(out));
    }

    // Writes the crowd's joints for one character (`joint_count()` rotations, as
    // `Crowd::read_joints` gives them) into your bone local rotations (`bone_count()`),
    // in place: each chain bone gets the rotation that, with the other bones as they are,
    // makes its joint's; other bones are left alone. On an error nothing is written.
    [[nodiscard]] cg_status try_write_joints(Span<const cg_quat> joints,
                                             Span<cg_quat> bone_rotations) const noexcept {
        return cg_rig_write_joints(raw(), joints.data(), joints.size(), bone_rotations.data(),
                                   bone_rotations.size());
    }
    void write_joints(Span<const cg_quat> joints, Span<cg_quat> bone_rotations) const {
        check(try_write_joints(joints, bone_rotations));
    }

   private:
    static bool sizes_match(std::size_t count, Span<const std::int32_t> parents,
                            Span<const cg_vec3> translations,
                            Span<const cg_quat> rotations) noexcept {
        return count <= CG_MAX_RIG_BONES && parents.size() == count &&
               translations.size() == count && (rotations.empty() || rotations.size() == count);
    }
    static bool no_nul(const std::vector<std::string>& names,
                       const std::string& bone_map) noexcept {
        for (const std::string& name : names) {
            if (name.find('\0') != std::string::npos) {
                return false;
            }
        }
        return bone_map.find('\0') == std::string::npos;
    }
};

// ---------------------------------------------------------------------------------------
// Dual quaternions and blending (free functions; thread-safe; allocate nothing).

// A rotation and a translation (your length unit).
struct RigidTransform {
    cg_quat rotation;
    cg_vec3 translation;
};

[[nodiscard]] inline cg_status try_dualquat_from_rt(const cg_quat& rotation,
                                                    const cg_vec3& translation,
                                                    cg_dualquat& out) noexcept {
    return cg_dualquat_from_rt(&rotation, &translation, &out);
}
// The transform "rotate by `rotation`, then translate by `translation`".
inline cg_dualquat dualquat_from_rt(const cg_quat& rotation, const cg_vec3& translation) {
    cg_dualquat out{};
    check(try_dualquat_from_rt(rotation, translation, out));
    return out;
}

[[nodiscard]] inline cg_status try_dualquat_to_rt(const cg_dualquat& dual_quat,
                                                  RigidTransform& out) noexcept {
    return cg_dualquat_to_rt(&dual_quat, &out.rotation, &out.translation);
}
inline RigidTransform dualquat_to_rt(const cg_dualquat& dual_quat) {
    RigidTransform out{};
    check(try_dualquat_to_rt(dual_quat, out));
    return out;
}

// `matrix`: 16 floats, column-major for column vectors (OSG's osg::Matrixf::ptr() as is).
[[nodiscard]] inline cg_status try_dualquat_from_matrix(const float* matrix,
                                                        cg_dualquat& out) noexcept {
    return cg_dualquat_from_matrix(matrix, &out);
}
inline cg_dualquat dualquat_from_matrix(const std::array<float, 16>& matrix) {
    cg_dualquat out{};
    check(try_dualquat_from_matrix(matrix.data(), out));
    return out;
}
inline cg_dualquat dualquat_from_matrix(const float* matrix) {
    cg_dualquat out{};
    check(try_dualquat_from_matrix(matrix, out));
    return out;
}

[[nodiscard]] inline cg_status try_dualquat_to_matrix(const cg_dualquat& dual_quat,
                                                      float* out16) noexcept {
    return cg_dualquat_to_matrix(&dual_quat, out16);
}
// The 4x4 matrix, column-major for column vectors.
inline std::array<float, 16> dualquat_to_matrix(const cg_dualquat& dual_quat) {
    std::array<float, 16> out{};
    check(try_dualquat_to_matrix(dual_quat, out.data()));
    return out;
}

// DLB of `inputs` with `weights` (same count).
[[nodiscard]] inline cg_status try_blend_dlb(Span<const cg_dualquat> inputs,
                                             Span<const float> weights,
                                             cg_dualquat& out) noexcept {
    if (inputs.size() != weights.size()) {
        return CG_STATUS_INVALID_ARGUMENT;
    }
    return cg_blend_dlb(inputs.data(), weights.data(), inputs.size(), &out);
}
inline cg_dualquat blend_dlb(Span<const cg_dualquat> inputs, Span<const float> weights) {
    detail::check_sizes(inputs.size() == weights.size(),
                        "crowdgaze::blend_dlb: inputs and weights differ in size");
    cg_dualquat out{};
    check(try_blend_dlb(inputs, weights, out));
    return out;
}

// DIB of `inputs` with `weights` (same count) into `out`; returns false (with `out` the best
// iterate) if `precision` was not reached in `max_iterations`.
[[nodiscard]] inline cg_status try_blend_dib(Span<const cg_dualquat> inputs,
                                             Span<const float> weights, float precision,
                                             std::uint32_t max_iterations,
                                             cg_dualquat& out) noexcept {
    if (inputs.size() != weights.size()) {
        return CG_STATUS_INVALID_ARGUMENT;
    }
    return cg_blend_dib(inputs.data(), weights.data(), inputs.size(), precision, max_iterations,
                        &out);
}
inline bool blend_dib(Span<const cg_dualquat> inputs, Span<const float> weights,
                      cg_dualquat& out, float precision = 1e-6f,
                      std::uint32_t max_iterations = 16) {
    detail::check_sizes(inputs.size() == weights.size(),
                        "crowdgaze::blend_dib: inputs and weights differ in size");
    return check_converged(try_blend_dib(inputs, weights, precision, max_iterations, out));
}

// DLB of whole poses: `keys` key-major (`weights.size()` keys of `out_pose.size()` joints).
[[nodiscard]] inline cg_status try_blend_pose_dlb(Span<const cg_dualquat> keys,
                                                  Span<const float> weights,
                                                  Span<cg_dualquat> out_pose) noexcept {
    if (keys.size() != weights.size() * out_pose.size()) {
        return CG_STATUS_INVALID_ARGUMENT;
    }
    return cg_blend_pose_dlb(keys.data(), weights.data(), weights.size(), out_pose.size(),
                             out_pose.data());
}
inline void blend_pose_dlb(Span<const cg_dualquat> keys, Span<const float> weights,
                           Span<cg_dualquat> out_pose) {
    detail::check_sizes(keys.size() == weights.size() * out_pose.size(),
                        "crowdgaze::blend_pose_dlb: keys.size() != weights.size() * joints");
    check(try_blend_pose_dlb(keys, weights, out_pose));
}

// DIB of whole poses; returns false if some joint missed the precision (all written).
[[nodiscard]] inline cg_status try_blend_pose_dib(Span<const cg_dualquat> keys,
                                                  Span<const float> weights,
                                                  Span<cg_dualquat> out_pose, float precision,
                                                  std::uint32_t max_iterations) noexcept {
    if (keys.size() != weights.size() * out_pose.size()) {
        return CG_STATUS_INVALID_ARGUMENT;
    }
    return cg_blend_pose_dib(keys.data(), weights.data(), weights.size(), out_pose.size(),
                             precision, max_iterations, out_pose.data());
}
inline bool blend_pose_dib(Span<const cg_dualquat> keys, Span<const float> weights,
                           Span<cg_dualquat> out_pose, float precision = 1e-6f,
                           std::uint32_t max_iterations = 16) {
    detail::check_sizes(keys.size() == weights.size() * out_pose.size(),
                        "crowdgaze::blend_pose_dib: keys.size() != weights.size() * joints");
    return check_converged(try_blend_pose_dib(keys, weights, out_pose, precision, max_iterations));
}

// The centre of a 3x4 row-major camera matrix P = K[R|t].
[[nodiscard]] inline cg_status try_camera_center_from_projection(const float* projection12,
                                                                 cg_vec3& out) noexcept {
    return cg_camera_center_from_projection(projection12, &out);
}
inline cg_vec3 camera_center_from_projection(const std::array<float, 12>& projection) {
    cg_vec3 out{};
    check(try_camera_center_from_projection(projection.data(), out));
    return out;
}

// ---------------------------------------------------------------------------------------
// View blender.

// Owns a `cg_view_blender*`: view-adaptive blending of key animations. Move-only. Knows its
// joint and key counts (from the config, or given when adopting a handle).
class ViewBlender : public Owner<cg_view_blender, cg_view_blender_destroy> {
   public:
    ViewBlender() noexcept = default;
    // Creates a blender from `config` (see `view_blender_config(joints, keys)`); throws.
    explicit ViewBlender(const cg_view_blender_config& config) {
        check(try_create(config, *this));
    }
    // Takes ownership of a blender created elsewhere with these counts.
    ViewBlender(cg_view_blender* adopted, std::uint32_t joint_count,
                std::uint32_t key_count) noexcept
        : Owner(adopted), joint_count_(joint_count), key_count_(key_count) {}

    [[nodiscard]] static cg_status try_create(const cg_view_blender_config& config,
                                              ViewBlender& out) noexcept {
        cg_view_blender* created = nullptr;
        const cg_status status = cg_view_blender_create(&config, &created);
        if (status == CG_STATUS_OK) {
            out.reset(created, config.joint_count, config.key_count);
        }
        return status;
    }

    ViewBlender(ViewBlender&& other) noexcept
        : Owner(std::move(other)),
          joint_count_(std::exchange(other.joint_count_, 0)),
          key_count_(std::exchange(other.key_count_, 0)) {}
    ViewBlender& operator=(ViewBlender&& other) noexcept {
        if (this != &other) {
            const std::uint32_t joints = other.joint_count_, keys = other.key_count_;
            reset(other.release(), joints, keys);
        }
        return *this;
    }
    ~ViewBlender() = default;

    // Gives up ownership (and the counts): the caller must `cg_view_blender_destroy` it.
    [[nodiscard]] cg_view_blender* release() noexcept {
        joint_count_ = 0;
        key_count_ = 0;
        return Owner::release();
    }
    // Destroys the blender held (if any) and takes `adopted` with its counts.
    void reset(cg_view_blender* adopted = nullptr, std::uint32_t joint_count = 0,
               std::uint32_t key_count = 0) noexcept {
        Owner::reset(adopted);
        joint_count_ = joint_count;
        key_count_ = key_count;
    }
    std::uint32_t joint_count() const noexcept { return joint_count_; }
    std::uint32_t key_count() const noexcept { return key_count_; }

    // Key `key` plays a clip: `frames` frame-major, `frames.size() / joint_count()` frames.
    [[nodiscard]] cg_status try_set_key_clip(std::uint32_t key, Span<const cg_dualquat> frames,
                                             float frames_per_second, bool looping) noexcept {
        if (joint_count_ == 0 || frames.size() % joint_count_ != 0) {
            return CG_STATUS_INVALID_ARGUMENT;
        }
        return cg_view_blender_set_key_clip(raw(), key, frames.data(),
                                            frames.size() / joint_count_, frames_per_second,
                                            looping);
    }
    void set_key_clip(std::uint32_t key, Span<const cg_dualquat> frames, float frames_per_second,
                      bool looping) {
        detail::check_sizes(joint_count_ != 0 && frames.size() % joint_count_ == 0,
                            "crowdgaze::ViewBlender::set_key_clip: frames.size() is not a "
                            "multiple of joint_count()");
        check(try_set_key_clip(key, frames, frames_per_second, looping));
    }

    // Key `key` is a static pose of `joint_count()` joints.
    [[nodiscard]] cg_status try_set_key_pose(std::uint32_t key,
                                             Span<const cg_dualquat> pose) noexcept {
        return cg_view_blender_set_key_pose(raw(), key, pose.data(), pose.size());
    }
    void set_key_pose(std::uint32_t key, Span<const cg_dualquat> pose) {
        check(try_set_key_pose(key, pose));
    }

    // A key camera: a direction in the character's frame, mapped to key `key`.
    [[nodiscard]] cg_status try_add_camera(cg_vec3 direction, std::uint32_t key) noexcept {
        return cg_view_blender_add_camera(raw(), direction, key);
    }
    void add_camera(cg_vec3 direction, std::uint32_t key) {
        check(try_add_camera(direction, key));
    }

    // The key weights (`key_count()` floats) for a viewer at `viewer`.
    [[nodiscard]] cg_status try_weights(const cg_dualquat& character, const cg_vec3& viewer,
                                        Span<float> out) const noexcept {
        return cg_view_blender_weights(raw(), &character, &viewer, out.data(), out.size());
    }
    void weights(const cg_dualquat& character, const cg_vec3& viewer, Span<float> out) const {
        check(try_weights(character, viewer, out));
    }
    // Allocates the vector.
    std::vector<float> weights(const cg_dualquat& character, const cg_vec3& viewer) const {
        std::vector<float> out(key_count_);
        weights(character, viewer, out);
        return out;
    }

    // The blended pose (`joint_count()` local transforms) at clip time `t`. Returns false
    // if DIB missed its precision somewhere (the pose is written all the same).
    [[nodiscard]] cg_status try_evaluate(const cg_dualquat& character, const cg_vec3& viewer,
                                         double t, Span<cg_dualquat> out_pose) const noexcept {
        return cg_view_blender_evaluate(raw(), &character, &viewer, t, out_pose.data(),
                                        out_pose.size());
    }
    bool evaluate(const cg_dualquat& character, const cg_vec3& viewer, double t,
                  Span<cg_dualquat> out_pose) const {
        return check_converged(try_evaluate(character, viewer, t, out_pose));
    }

   private:
    std::uint32_t joint_count_ = 0;
    std::uint32_t key_count_ = 0;
};

}  // namespace crowdgaze

#endif  // CROWDGAZE_HPP
