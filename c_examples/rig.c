/* rig.c: your own skeleton in one call. A Mixamo-style skeleton (names `mixamorig:Hips`,
 * `mixamorig:Spine` ... `mixamorig:Head`, eyes, arms and legs; Y up, facing +Z,
 * centimetres, bones with rotated rest frames as FBX imports have) is mapped to a gaze chain
 * with cg_rig_create, its chain added to a crowd in centimetres, and each frame the engine's
 * bone rotations (a small sway) go through cg_rig_base_pose into the crowd, and the crowd's
 * joints come back through cg_rig_write_joints into the bones. Forward kinematics over the
 * bones then checks that the head bone turned exactly as the crowd's chain says and that the
 * eye bones look at the target. Last, the hierarchy of a BVH file (the path in argv[1], else
 * $CG_DATA_DIR/bvh/wave_hello.bvh) is mapped too, and driven from its rest pose to look at
 * a point: its chain bones turn, no other bone does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "crowdgaze.h"

#define FPS 30
#define PI_F 3.14159265f
#define BONES 25
#define MAX_BVH_BONES 256

static int failures = 0;
#define CHECK(cond)                                                                       \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);    \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

static void ok(cg_status status, const char *what) {
    if (status != CG_STATUS_OK) {
        char message[512];
        cg_last_error_message(message, sizeof message);
        fprintf(stderr, "%s: %s\n", what, message);
        exit(1);
    }
}

/* ---- quaternions and vectors ---------------------------------------------------------- */

static cg_quat quat(float x, float y, float z, float w) {
    cg_quat q;
    q.x = x;
    q.y = y;
    q.z = z;
    q.w = w;
    return q;
}

static cg_vec3 vec3(float x, float y, float z) {
    cg_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static cg_quat axis_angle(float x, float y, float z, float degrees) {
    float half = 0.5f * degrees * PI_F / 180.0f;
    return quat(x * sinf(half), y * sinf(half), z * sinf(half), cosf(half));
}

static cg_quat mul(cg_quat a, cg_quat b) {
    return quat(a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}

static cg_quat inverse(cg_quat q) { return quat(-q.x, -q.y, -q.z, q.w); }

static cg_vec3 rotate(cg_quat q, cg_vec3 v) {
    cg_quat r = mul(mul(q, quat(v.x, v.y, v.z, 0.0f)), inverse(q));
    return vec3(r.x, r.y, r.z);
}

static cg_vec3 add(cg_vec3 a, cg_vec3 b) { return vec3(a.x + b.x, a.y + b.y, a.z + b.z); }
static cg_vec3 sub(cg_vec3 a, cg_vec3 b) { return vec3(a.x - b.x, a.y - b.y, a.z - b.z); }

/* The angle between two directions, degrees. */
static float angle_between(cg_vec3 a, cg_vec3 b) {
    float dot = a.x * b.x + a.y * b.y + a.z * b.z;
    float la = sqrtf(a.x * a.x + a.y * a.y + a.z * a.z);
    float lb = sqrtf(b.x * b.x + b.y * b.y + b.z * b.z);
    float c = dot / (la * lb);
    if (c > 1.0f) c = 1.0f;
    if (c < -1.0f) c = -1.0f;
    return acosf(c) * 180.0f / PI_F;
}

/* The angle of the rotation from a to b, degrees. */
static float rotation_angle(cg_quat a, cg_quat b) {
    cg_quat d = mul(inverse(a), b);
    float w = fabsf(d.w) > 1.0f ? 1.0f : fabsf(d.w);
    return 2.0f * acosf(w) * 180.0f / PI_F;
}

/* ---- the Mixamo skeleton ---------------------------------------------------------------- */

typedef struct {
    const char *name;
    int parent;
    float position[3]; /* at rest, relative to the character, centimetres */
    cg_quat rotation;  /* at rest, relative to the character */
} rest_bone;

static const char *names[BONES] = {
    "mixamorig:Hips",         "mixamorig:Spine",        "mixamorig:Spine1",
    "mixamorig:Spine2",       "mixamorig:Neck",         "mixamorig:Head",
    "mixamorig:HeadTop_End",  "mixamorig:LeftEye",      "mixamorig:RightEye",
    "mixamorig:LeftShoulder", "mixamorig:LeftArm",      "mixamorig:LeftForeArm",
    "mixamorig:LeftHand",     "mixamorig:RightShoulder", "mixamorig:RightArm",
    "mixamorig:RightForeArm", "mixamorig:RightHand",    "mixamorig:LeftUpLeg",
    "mixamorig:LeftLeg",      "mixamorig:LeftFoot",     "mixamorig:LeftToeBase",
    "mixamorig:RightUpLeg",   "mixamorig:RightLeg",     "mixamorig:RightFoot",
    "mixamorig:RightToeBase",
};
enum { HIPS = 0, SPINE = 1, SPINE1 = 2, NECK = 4, HEAD = 5, LEFT_EYE = 7, RIGHT_EYE = 8 };

/* Rest poses relative to the character: the spine tilts a little, the arms are rolled
 * along their length and the legs point down, as FBX imports have them. */
static void mixamo(rest_bone bones[BONES]) {
    static const int parents[BONES] = {-1, 0, 1, 2, 3, 4, 5, 5, 5, 3, 9, 10, 11,
                                       3,  13, 14, 15, 0, 17, 18, 19, 0, 21, 22, 23};
    static const float positions[BONES][3] = {
        {0, 100, 0},    {0, 110, 1},    {0, 122, 1.5f}, {0, 135, 1},    {0, 150, 0},
        {0, 160, 1.5f}, {0, 178, 2},    {3.2f, 165, 9}, {-3.2f, 165, 9}, {6, 145, 0},
        {16, 145, 0},   {44, 145, 0},   {70, 145, 0},   {-6, 145, 0},   {-16, 145, 0},
        {-44, 145, 0},  {-70, 145, 0},  {9, 95, 0},     {9, 52, 0.5f},  {9, 8, -1},
        {9, 2, 12},     {-9, 95, 0},    {-9, 52, 0.5f}, {-9, 8, -1},    {-9, 2, 12},
    };
    static const float tilts[7] = {-3, 4, 6, 2, -10, 5, 5};
    int i;
    for (i = 0; i < BONES; i++) {
        bones[i].name = names[i];
        bones[i].parent = parents[i];
        memcpy(bones[i].position, positions[i], sizeof positions[i]);
        if (i < 7) {
            bones[i].rotation = axis_angle(1, 0, 0, tilts[i]);
        } else if (i < 9) {
            bones[i].rotation = quat(0, 0, 0, 1);
        } else if (i < 17) {
            bones[i].rotation = axis_angle(0, 0, 1, i < 13 ? -90.0f : 90.0f);
        } else {
            bones[i].rotation = axis_angle(1, 0, 0, 180.0f);
        }
    }
}

/* Forward kinematics: each bone's rotation and position relative to the character. */
static void globals_of(const int *parents, const cg_vec3 *translations, const cg_quat *locals,
                       int count, cg_quat *rotations, cg_vec3 *positions) {
    int i;
    for (i = 0; i < count; i++) {
        if (parents[i] < 0) {
            rotations[i] = locals[i];
            positions[i] = translations[i];
        } else {
            int p = parents[i];
            rotations[i] = mul(rotations[p], locals[i]);
            positions[i] = add(positions[p], rotate(rotations[p], translations[i]));
        }
    }
}

static void print_report_line(const cg_rig *rig, const char *label) {
    char report[4096];
    size_t length = cg_rig_report(rig, report, sizeof report);
    char *newline = strchr(report, '\n');
    CHECK(length > 0 && length < sizeof report);
    if (newline) *newline = '\0';
    printf("%s: %s\n", label, report);
}

static int mixamo_example(void) {
    rest_bone rest[BONES];
    int parents[BONES];
    cg_vec3 translations[BONES], positions[BONES], eye_forward[2], head_forward;
    cg_quat rest_locals[BONES], bones[BONES], rotations[BONES];
    cg_quat base[CG_MAX_CHAIN_JOINTS], joints[CG_MAX_CHAIN_JOINTS];
    uint32_t chain_bones[CG_MAX_CHAIN_JOINTS], roles[BONES], joint_count = 0;
    cg_rig_desc desc;
    cg_rig *rig = NULL;
    cg_chain_desc chain;
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    cg_character_desc character;
    cg_gaze_target target;
    cg_entity_state state;
    uint32_t id;
    int i, frame;
    float worst_head = 0.0f, worst_eye = 0.0f, head_turn = 0.0f;

    /* The engine's skeleton: local translations and rotations from the rest globals. */
    mixamo(rest);
    for (i = 0; i < BONES; i++) {
        cg_vec3 position = vec3(rest[i].position[0], rest[i].position[1], rest[i].position[2]);
        parents[i] = rest[i].parent;
        if (rest[i].parent < 0) {
            translations[i] = position;
            rest_locals[i] = rest[i].rotation;
        } else {
            const rest_bone *p = &rest[rest[i].parent];
            cg_vec3 from = vec3(p->position[0], p->position[1], p->position[2]);
            translations[i] = rotate(inverse(p->rotation), sub(position, from));
            rest_locals[i] = mul(inverse(p->rotation), rest[i].rotation);
        }
    }

    /* 1. The rig, in one call: axes detected, centimetres, for a crowd in centimetres. */
    desc.struct_size = sizeof desc;
    ok(cg_rig_desc_init(&desc), "cg_rig_desc_init");
    desc.bone_count = BONES;
    desc.bone_names = names;
    desc.parents = parents;
    desc.rest_translations = translations;
    desc.rest_rotations = rest_locals;
    desc.units_per_metre = 100.0f;
    desc.crowd_units_per_metre = 100.0f;
    ok(cg_rig_create(&desc, &rig), "cg_rig_create");
    print_report_line(rig, "Mixamo");
    ok(cg_rig_joint_count(rig, &joint_count), "cg_rig_joint_count");
    ok(cg_rig_chain_bones(rig, chain_bones, CG_MAX_CHAIN_JOINTS), "cg_rig_chain_bones");
    ok(cg_rig_bone_roles(rig, roles, BONES), "cg_rig_bone_roles");
    CHECK(joint_count == 7);
    CHECK(chain_bones[0] == SPINE && chain_bones[4] == HEAD && chain_bones[5] == LEFT_EYE);
    CHECK(roles[HIPS] == CG_BONE_ROLE_ROOT && roles[NECK] == CG_BONE_ROLE_NECK);
    CHECK(roles[RIGHT_EYE] == CG_BONE_ROLE_RIGHT_EYE && roles[10] == CG_BONE_ROLE_NONE);

    /* Each eye bone's forward in its own frame: the character's +Z at rest. */
    globals_of(parents, translations, rest_locals, BONES, rotations, positions);
    eye_forward[0] = rotate(inverse(rotations[LEFT_EYE]), vec3(0, 0, 1));
    eye_forward[1] = rotate(inverse(rotations[RIGHT_EYE]), vec3(0, 0, 1));
    head_forward = rotate(inverse(rotations[HEAD]), vec3(0, 0, 1));

    /* 2. A crowd in centimetres, and the character with the rig's chain. */
    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "cg_crowd_config_init");
    config.units_per_metre = 100.0f;
    config.max_characters = 1;
    config.max_objects = 0;
    ok(cg_crowd_create(&config, &crowd), "cg_crowd_create");
    chain.struct_size = sizeof chain;
    ok(cg_rig_chain(rig, &chain), "cg_rig_chain");
    character.struct_size = sizeof character;
    ok(cg_character_desc_init(&character), "cg_character_desc_init");
    character.chain = &chain;
    ok(cg_crowd_add_character(crowd, &character, &id), "cg_crowd_add_character");

    /* A point 25 degrees to the character's left, at eye height, 3 m away. */
    target.struct_size = sizeof target;
    ok(cg_gaze_target_init(&target), "cg_gaze_target_init");
    target.point = vec3(300.0f * sinf(25.0f * PI_F / 180.0f), 165.0f,
                        300.0f * cosf(25.0f * PI_F / 180.0f));
    ok(cg_crowd_set_gaze_target(crowd, id, &target), "cg_crowd_set_gaze_target");
    state.struct_size = sizeof state;
    ok(cg_entity_state_init(&state), "cg_entity_state_init");
    state.id = id;

    /* 3. Each frame: animation -> base pose -> crowd -> joints -> bones. */
    for (frame = 1; frame <= 3 * FPS; frame++) {
        float t = (float)frame / FPS;
        cg_quat head_from_chain = quat(0, 0, 0, 1);
        memcpy(bones, rest_locals, sizeof bones);
        bones[SPINE] = mul(bones[SPINE], axis_angle(0, 1, 0, 4.0f * sinf(1.7f * t)));
        bones[SPINE1] = mul(bones[SPINE1], axis_angle(1, 0, 0, 2.0f * sinf(2.3f * t)));
        bones[NECK] = mul(bones[NECK], axis_angle(0, 0, 1, 3.0f * sinf(1.1f * t)));
        ok(cg_rig_base_pose(rig, bones, BONES, base, CG_MAX_CHAIN_JOINTS), "cg_rig_base_pose");
        ok(cg_crowd_set_base_pose(crowd, id, base, joint_count), "cg_crowd_set_base_pose");
        ok(cg_crowd_push_frame(crowd, (double)t, &state, 1), "cg_crowd_push_frame");
        ok(cg_crowd_step(crowd, 1.0f / FPS), "cg_crowd_step");
        ok(cg_crowd_read_joints(crowd, 0, 1, joints, CG_MAX_CHAIN_JOINTS), "read_joints");
        ok(cg_rig_write_joints(rig, joints, joint_count, bones, BONES), "cg_rig_write_joints");

        /* The head bone, by forward kinematics over the bones, turns as the chain says (the
         * chain root's frame is the character's, at heading 0). */
        globals_of(parents, translations, bones, BONES, rotations, positions);
        for (i = 0; i < 5; i++) head_from_chain = mul(head_from_chain, joints[i]);
        if (rotation_angle(head_from_chain, rotations[HEAD]) > worst_head)
            worst_head = rotation_angle(head_from_chain, rotations[HEAD]);
        head_turn = angle_between(rotate(rotations[HEAD], head_forward), vec3(0, 0, 1));
        if (frame >= 2 * FPS) {
            /* Settled: each eye bone looks at the target. */
            int e;
            for (e = 0; e < 2; e++) {
                int b = e == 0 ? LEFT_EYE : RIGHT_EYE;
                cg_vec3 looking = rotate(rotations[b], eye_forward[e]);
                float off = angle_between(looking, sub(target.point, positions[b]));
                if (off > worst_eye) worst_eye = off;
            }
        }
    }
    printf("head bone vs the crowd's chain: %.3f deg at worst\n", worst_head);
    printf("head turned %.1f deg towards the target 25 deg left\n", head_turn);
    printf("eye bones off the target: %.2f deg at worst over the last second\n", worst_eye);
    CHECK(worst_head < 0.25f); /* float acos near 1 */
    CHECK(head_turn > 5.0f && head_turn < 25.0f);
    CHECK(worst_eye < 2.0f);

    cg_crowd_destroy(crowd);
    cg_rig_destroy(rig);
    return 0;
}

/* ---- a BVH hierarchy -------------------------------------------------------------------- */

typedef struct {
    char names[MAX_BVH_BONES][64];
    const char *name_pointers[MAX_BVH_BONES];
    int parents[MAX_BVH_BONES];
    cg_vec3 offsets[MAX_BVH_BONES];
    int count;
} bvh_skeleton;

/* Reads the HIERARCHY section of a BVH file: joint names, parents and offsets (End Sites
 * are left out). Returns 0 on success. */
static int read_bvh(const char *path, bvh_skeleton *out) {
    FILE *file = fopen(path, "r");
    char word[128];
    int stack[MAX_BVH_BONES + 1], depth = 0, current = -1, in_end_site = 0, end_depth = 0;
    if (!file) return -1;
    out->count = 0;
    while (fscanf(file, "%127s", word) == 1) {
        if (strcmp(word, "MOTION") == 0) break;
        if (strcmp(word, "ROOT") == 0 || strcmp(word, "JOINT") == 0) {
            if (out->count == MAX_BVH_BONES || fscanf(file, "%63s", out->names[out->count]) != 1)
                break;
            out->parents[out->count] = depth > 0 ? stack[depth - 1] : -1;
            current = out->count++;
        } else if (strcmp(word, "End") == 0) {
            in_end_site = 1;
            end_depth = depth;
        } else if (strcmp(word, "{") == 0) {
            if (!in_end_site) stack[depth] = current;
            depth++;
        } else if (strcmp(word, "}") == 0) {
            depth--;
            if (in_end_site && depth == end_depth) in_end_site = 0;
        } else if (strcmp(word, "OFFSET") == 0) {
            cg_vec3 offset;
            if (fscanf(file, "%f %f %f", &offset.x, &offset.y, &offset.z) != 3) break;
            if (!in_end_site) out->offsets[current] = offset;
        }
    }
    fclose(file);
    return out->count > 0 ? 0 : -1;
}

/* Drives the BVH character for two seconds from its rest pose in a crowd of its units,
 * looking at a point to its side: the chain bones turn, the others stay. */
static void drive_bvh(const cg_rig *rig, uint32_t bone_count) {
    static cg_quat bones[MAX_BVH_BONES];
    cg_quat base[CG_MAX_CHAIN_JOINTS], joints[CG_MAX_CHAIN_JOINTS];
    uint32_t joint_count, chain_bones[CG_MAX_CHAIN_JOINTS], b, frame, moved = 0;
    cg_crowd_config config;
    cg_crowd *crowd = NULL;
    cg_chain_desc chain;
    cg_character_desc character;
    cg_gaze_target target;
    cg_entity_state state;
    uint32_t id;
    ok(cg_rig_joint_count(rig, &joint_count), "cg_rig_joint_count (BVH)");
    ok(cg_rig_chain_bones(rig, chain_bones, CG_MAX_CHAIN_JOINTS), "cg_rig_chain_bones (BVH)");
    config.struct_size = sizeof config;
    ok(cg_crowd_config_init(&config), "cg_crowd_config_init");
    config.max_characters = 1;
    config.max_objects = 0;
    ok(cg_crowd_create(&config, &crowd), "cg_crowd_create (BVH)");
    chain.struct_size = sizeof chain;
    ok(cg_rig_chain(rig, &chain), "cg_rig_chain (BVH)");
    character.struct_size = sizeof character;
    ok(cg_character_desc_init(&character), "cg_character_desc_init");
    character.chain = &chain;
    ok(cg_crowd_add_character(crowd, &character, &id), "cg_crowd_add_character (BVH)");
    target.struct_size = sizeof target;
    ok(cg_gaze_target_init(&target), "cg_gaze_target_init");
    target.point = vec3(2.0f, 1.5f, 2.0f);
    ok(cg_crowd_set_gaze_target(crowd, id, &target), "cg_crowd_set_gaze_target (BVH)");
    state.struct_size = sizeof state;
    ok(cg_entity_state_init(&state), "cg_entity_state_init");
    state.id = id;
    for (frame = 1; frame <= 2 * FPS; frame++) {
        for (b = 0; b < bone_count; b++) bones[b] = quat(0, 0, 0, 1); /* the rest pose */
        ok(cg_rig_base_pose(rig, bones, bone_count, base, CG_MAX_CHAIN_JOINTS), "base (BVH)");
        ok(cg_crowd_set_base_pose(crowd, id, base, joint_count), "set_base_pose (BVH)");
        ok(cg_crowd_push_frame(crowd, (double)frame / FPS, &state, 1), "push (BVH)");
        ok(cg_crowd_step(crowd, 1.0f / FPS), "step (BVH)");
        ok(cg_crowd_read_joints(crowd, 0, 1, joints, CG_MAX_CHAIN_JOINTS), "read (BVH)");
        ok(cg_rig_write_joints(rig, joints, joint_count, bones, bone_count), "write (BVH)");
    }
    for (b = 0; b < bone_count; b++) {
        uint32_t k, in_chain = 0;
        for (k = 0; k < joint_count; k++) in_chain |= chain_bones[k] == b;
        if (rotation_angle(bones[b], quat(0, 0, 0, 1)) > 0.5f) {
            CHECK(in_chain); /* only chain bones turn */
            moved++;
        }
    }
    printf("BVH character driven: %u of %u chain bones turned to the target\n", moved,
           joint_count);
    CHECK(moved >= 2);
    cg_crowd_destroy(crowd);
}

static int bvh_example(const char *path) {
    static bvh_skeleton skeleton;
    const char *slash = strrchr(path, '/');
    cg_rig_desc desc;
    cg_rig *rig = NULL;
    int i;
    if (read_bvh(path, &skeleton) != 0) {
        fprintf(stderr, "cannot read the hierarchy of %s\n", path);
        return 1;
    }
    for (i = 0; i < skeleton.count; i++) skeleton.name_pointers[i] = skeleton.names[i];
    desc.struct_size = sizeof desc;
    ok(cg_rig_desc_init(&desc), "cg_rig_desc_init");
    desc.bone_count = (uint32_t)skeleton.count;
    desc.bone_names = skeleton.name_pointers;
    desc.parents = skeleton.parents;
    desc.rest_translations = skeleton.offsets;
    desc.rest_rotations = NULL; /* BVH rest poses have no rotation */
    desc.units_per_metre = 25.0f; /* this capture's units are about 4 cm */
    ok(cg_rig_create(&desc, &rig), "cg_rig_create (BVH)");
    printf("BVH %s, %d joints\n", slash ? slash + 1 : path, skeleton.count);
    print_report_line(rig, "BVH");
    drive_bvh(rig, (uint32_t)skeleton.count);
    cg_rig_destroy(rig);
    return 0;
}

int main(int argc, char **argv) {
    char path[1024];
    const char *data = getenv("CG_DATA_DIR");
    if (argc > 1) {
        snprintf(path, sizeof path, "%s", argv[1]);
    } else {
        snprintf(path, sizeof path, "%s/bvh/wave_hello.bvh", data ? data : "../shared/data");
    }
    if (mixamo_example() != 0 || bvh_example(path) != 0) return 1;
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("ok\n");
    return 0;
}
