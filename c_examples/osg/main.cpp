// osg_street: crowdgaze in an OpenSceneGraph 3.6 scene.
//
// A pedestrian street (Z up, the street along +Y): walkers go up and down, three bystanders
// stand by, three friends stand together on the right pavement and talk in turns, lamps and
// shop windows line it. Every character is a small articulated figure on one skeleton, a
// table of bones with Mixamo names (`mixamorig:Hips`, `Spine`, `Spine1`, `Spine2`, `Neck`,
// `Head`, `LeftEye`, `RightEye`, the arms and the legs; rest offsets in metres, Z up, facing
// +Y): one osg::MatrixTransform per bone, parented as the table says, with the body's boxes,
// the head, the eyes (a white ball, a dark pupil) and under the head the nose, the mouth
// and two upper eyelids (skin-coloured half shells over the eye balls) that follow the
// eyes' pitch and close when the character blinks.
//
// The skeleton is mapped to a gaze chain once (`crowdgaze::Rig`, `cg_rig_create`: spine,
// neck, head and eyes found by their names, in the crowd's axes and units) and every
// character is added with the rig's chain. Each frame the root node's update callback moves
// the walkers, poses each character's bones (legs and arms swinging, the rest at rest),
// turns the pose into the crowd's base pose (`cg_rig_base_pose`, `cg_crowd_set_base_pose`),
// pushes the states, steps the crowd once (`cg_crowd_push_frame`, `cg_crowd_step`) and reads
// every character's eyelids with one call (`cg_crowd_read_eyelids`); then one update
// callback per character (an osg::NodeCallback on its root transform) reads that
// character's chain (`cg_crowd_read_joints`), writes it into its bone rotations
// (`cg_rig_write_joints`), sets every bone's transform from its rotation and rest offset,
// and turns its lids.
//
// The three friends are a conversation of the crowd (`set_conversation`); their
// turns are scripted by frame — each talks for 2.5 s, then a pause of 0.5 s, then the next —
// and pushed with `CG_STATE_TALKING` in their states. Crowdgaze has the listeners look at the
// speaker, the speaker at them now and then. Whoever talks opens and closes a mouth and has
// a yellow marker above the head.
//
// The scene is rendered offscreen — into a window of a virtual X server (run it under
// xvfb-run, with Mesa's software OpenGL), or a pbuffer — and frames are written as PNG files.
//
// Usage: osg_street OUTDIR [WIDTHxHEIGHT] [SECONDS]
// Env:   OSG_STREET_BLINK_RATE=N: the crowd's mean blink rate, blinks per minute (default
//        the library's, 17), e.g. 120 to catch closed lids in the frames.
//        OSG_STREET_SURFACE=pbuffer: render into a GLX pbuffer instead of a window.
//        OSG_STREET_SCENE=look-up: four more people stand on the left pavement and, from
//        2 s on, stare at a point 9 m up the facade across the street (an orange mark),
//        each with an overriding point target (`cg_crowd_set_gaze_target`), seen by a
//        camera that frames them and the point.
// Prints the first line of the rig's report, then for every written frame its file, each
// character's head rotation in its body frame (x y z w) and yaw, each character's lid
// closure and pitch, where the red-nosed bystander's nose is on the image, and for each
// member of the group whether it talks and the id of what it looks at ("talk" lines); with
// the look-up scene, the lookers and the point, then every frame each looker's head pitch in
// its body frame, degrees, up positive ("look" lines); "ok" last.
#include "crowdgaze.hpp"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/Image>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/NodeCallback>
#include <osg/ShapeDrawable>
#include <osg/Version>
#include <osgDB/WriteFile>
#include <osgViewer/Viewer>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

// ---------------------------------------------------------------------------------------
// The figures' skeleton, as an engine would hold it: bones with Mixamo's names, parents before
// children, rest offsets from the parent in the parent's frame (metres, Z up, facing +Y; the
// character's left is -X), rest rotations identity. The pelvis, spine, neck, head and eyes
// sit where the library's human chain (`cg_chain_desc_init_human`) has its joints: pelvis
// 0.95, spine from 1.00 to 1.40, neck 1.46, head 1.56, eyes 1.62 and 64 mm apart. The rig
// maps it by the names to a chain of 7 joints: 3 spine, the neck, the head, 2 eyes.

enum Bone : int {
    kHips, kSpine, kSpine1, kSpine2, kNeck, kHead, kLeftEye, kRightEye,
    kLeftArm, kRightArm, kLeftUpLeg, kRightUpLeg, kBones
};

struct BoneDesc {
    const char* name;
    int parent;  // -1: none (the character's root)
    cg_vec3 offset;
};

const BoneDesc kSkeleton[kBones] = {
    {"mixamorig:Hips", -1, {0.0f, 0.0f, 0.95f}},
    {"mixamorig:Spine", kHips, {0.0f, 0.0f, 0.05f}},
    {"mixamorig:Spine1", kSpine, {0.0f, 0.0f, 0.2f}},
    {"mixamorig:Spine2", kSpine1, {0.0f, 0.0f, 0.2f}},
    {"mixamorig:Neck", kSpine2, {0.0f, 0.0f, 0.06f}},
    {"mixamorig:Head", kNeck, {0.0f, 0.0f, 0.1f}},
    {"mixamorig:LeftEye", kHead, {-0.032f, 0.085f, 0.06f}},
    {"mixamorig:RightEye", kHead, {0.032f, 0.085f, 0.06f}},
    {"mixamorig:LeftArm", kSpine2, {-0.25f, 0.0f, 0.02f}},
    {"mixamorig:RightArm", kSpine2, {0.25f, 0.0f, 0.02f}},
    {"mixamorig:LeftUpLeg", kHips, {-0.1f, 0.0f, -0.05f}},
    {"mixamorig:RightUpLeg", kHips, {0.1f, 0.0f, -0.05f}},
};

constexpr double kFps = 24.0;
constexpr float kPi = 3.14159265358979f;
const osg::Vec3 kNose(0.0f, 0.1f, 0.03f);  // the red nose's centre in the head's frame
// The upper eyelids: half shells round the eye balls (radius 0.022; the pupils stand out to
// 0.027), turned about the head's x axis (the character's right). At 0 the lid's edge runs
// level through the eye's centre; positive turns it up.
constexpr float kLidRadius = 0.029f;
constexpr float kLidOpen = 0.45f;    // the open lid's edge above the eye's pitch, radians
constexpr float kLidClosed = -1.1f;  // the closed lid's edge: below the pupil, radians
// The group's turns: each member talks kTalkFrames frames, then nobody for kPauseFrames.
constexpr int kTalkFrames = 60;   // 2.5 s at 24 fps
constexpr int kPauseFrames = 12;  // 0.5 s
// The look-up scene: the lookers stare from this frame on (2 s), at this point (metres, on
// the right facade, x = 7, of the 11 m block at y = -15).
constexpr int kLookFrame = 48;
const cg_vec3 kLookPoint = {6.95f, -12.0f, 9.0f};
const osg::Vec3 kMouth(0.0f, 0.045f, 0.008f);  // the mouth's centre in the head's frame

// ---------------------------------------------------------------------------------------
// Geometry helpers.

osg::ref_ptr<osg::Geode> box(const osg::Vec3& centre, const osg::Vec3& size, const osg::Vec4& colour) {
    osg::ref_ptr<osg::ShapeDrawable> shape =
        new osg::ShapeDrawable(new osg::Box(centre, size.x(), size.y(), size.z()));
    shape->setColor(colour);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(shape);
    return geode;
}

osg::ref_ptr<osg::Geode> sphere(const osg::Vec3& centre, float radius, const osg::Vec4& colour) {
    osg::ref_ptr<osg::TessellationHints> hints = new osg::TessellationHints;
    hints->setDetailRatio(0.6f);
    osg::ref_ptr<osg::ShapeDrawable> shape =
        new osg::ShapeDrawable(new osg::Sphere(centre, radius), hints.get());
    shape->setColor(colour);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(shape);
    return geode;
}

osg::ref_ptr<osg::Geode> cylinder(const osg::Vec3& centre, float radius, float height,
                                  const osg::Vec4& colour) {
    osg::ref_ptr<osg::ShapeDrawable> shape =
        new osg::ShapeDrawable(new osg::Cylinder(centre, radius, height));
    shape->setColor(colour);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(shape);
    return geode;
}

// An upper eyelid: the half of a sphere above its equator (z >= 0), facing out, in one
// colour. Turned about x, its edge (the equator) sweeps over the eye.
osg::ref_ptr<osg::Geode> eyelid_shell(float radius, const osg::Vec4& colour) {
    constexpr int kRings = 6, kSegments = 20;
    osg::ref_ptr<osg::Geometry> shell = new osg::Geometry;
    osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
    osg::ref_ptr<osg::Vec3Array> normals = new osg::Vec3Array;
    for (int ring = 0; ring < kRings; ring++) {
        const float low = 0.5f * kPi * static_cast<float>(ring) / kRings;
        const float high = 0.5f * kPi * static_cast<float>(ring + 1) / kRings;
        const GLint first = static_cast<GLint>(vertices->size());
        for (int segment = 0; segment <= kSegments; segment++) {
            const float around = 2.0f * kPi * static_cast<float>(segment) / kSegments;
            for (const float latitude : {high, low}) {
                const osg::Vec3 normal(std::cos(latitude) * std::cos(around),
                                       std::cos(latitude) * std::sin(around), std::sin(latitude));
                vertices->push_back(normal * radius);
                normals->push_back(normal);
            }
        }
        shell->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_STRIP, first, 2 * (kSegments + 1)));
    }
    shell->setVertexArray(vertices);
    shell->setNormalArray(normals, osg::Array::BIND_PER_VERTEX);
    osg::ref_ptr<osg::Vec4Array> colours = new osg::Vec4Array;
    colours->push_back(colour);
    shell->setColorArray(colours, osg::Array::BIND_OVERALL);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(shell);
    return geode;
}

// An upper lid's transform in the head's frame: at the eye's centre, its edge at the lid's
// pitch (radians, up positive) blended towards closed by the blink's closure (0 open, 1
// closed).
osg::Matrix eyelid_matrix(float lid_pitch, float closure, const cg_vec3& eye_offset) {
    const float edge = (1.0f - closure) * (kLidOpen + lid_pitch) + closure * kLidClosed;
    return osg::Matrix::rotate(edge, osg::X_AXIS) *
           osg::Matrix::translate(eye_offset.x, eye_offset.y, eye_offset.z);
}

osg::Matrix local_matrix(const cg_quat& q, const cg_vec3& offset) {
    // Row vectors: rotate about the joint's origin, then place it in its parent.
    return osg::Matrix::rotate(osg::Quat(q.x, q.y, q.z, q.w)) *
           osg::Matrix::translate(offset.x, offset.y, offset.z);
}

osg::Quat to_osg(const cg_quat& q) { return osg::Quat(q.x, q.y, q.z, q.w); }

// Yaw in degrees (counter-clockwise about +Z from +Y) of the body's forward turned by q.
double yaw_degrees(const osg::Quat& q) {
    const osg::Vec3d forward = q * osg::Vec3d(0.0, 1.0, 0.0);
    return std::atan2(-forward.x(), forward.y()) * 180.0 / kPi;
}

// ---------------------------------------------------------------------------------------
// The street.

struct Character {
    std::uint32_t id = 0;
    std::uint32_t index = 0;  // place in the crowd's character order
    osg::Vec3 position;
    float heading = 0.0f;     // radians, counter-clockwise about +Z, 0 along +Y
    float speed = 0.0f;       // walkers: metres per second along the heading
    float turn_at = 20.0f;    // walkers turn round at |y| = turn_at
    float phase = 0.0f;       // walk cycle
    osg::ref_ptr<osg::MatrixTransform> root;  // the character's place and heading
    // One transform per bone of kSkeleton, and the bones' local rotations: the animation's
    // pose before the step, with the crowd's gaze written in after it.
    std::array<osg::ref_ptr<osg::MatrixTransform>, kBones> bones;
    std::array<cg_quat, kBones> pose{};
    osg::ref_ptr<osg::MatrixTransform> lid_left, lid_right;  // upper eyelids, under the head
    // Members of the group: a mouth that opens while talking and a marker above the head.
    osg::ref_ptr<osg::MatrixTransform> mouth;
    osg::ref_ptr<osg::Node> talk_marker;
    bool talking = false;

    // The animation's pose this frame: the legs and arms swing while walking, every other
    // bone (the chain's included) at rest.
    void animate() {
        const float swing = speed > 0.0f ? 0.45f * std::sin(phase) : 0.0f;
        const auto about_x = [](float angle) {
            return cg_quat{std::sin(0.5f * angle), 0.0f, 0.0f, std::cos(0.5f * angle)};
        };
        pose.fill(cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
        pose[kLeftUpLeg] = about_x(swing);
        pose[kRightUpLeg] = about_x(-swing);
        pose[kLeftArm] = about_x(-0.7f * swing);
        pose[kRightArm] = about_x(0.7f * swing);
    }
};

struct Street {
    crowdgaze::Crowd crowd;
    crowdgaze::Rig rig;  // kSkeleton mapped to a gaze chain, shared by every character
    cg_chain_desc chain{};
    std::vector<cg_quat> base, joints;  // one character's chain joints (scratch, per frame)
    std::vector<Character> characters;
    std::vector<cg_entity_state> states;
    std::vector<cg_eyelids> eyelids;  // every character's, in the crowd's order, each frame
    int frame = 0;
    std::size_t observer = 0;  // the red-nosed bystander
    std::uint32_t observed_walker = 0;
    std::vector<std::size_t> group;  // the friends talking together (character indices)
    std::uint32_t conversation = 0;  // their conversation's id
    std::vector<std::size_t> lookers;  // the look-up scene's group (character indices)

    // The member of the group talking at frame `f` (an index into `group`), or -1 in a pause.
    int speaker_at(int f) const {
        const int turn = f / (kTalkFrames + kPauseFrames);
        if (group.empty() || f % (kTalkFrames + kPauseFrames) >= kTalkFrames) return -1;
        return turn % static_cast<int>(group.size());
    }

    void advance() {
        frame++;
        const float dt = static_cast<float>(1.0 / kFps);
        if (frame == kLookFrame) {
            // The group looks up: game logic gives each an overriding point target.
            for (const std::size_t i : lookers) {
                crowd.set_gaze_target(characters[i].id, crowdgaze::gaze_target_point(kLookPoint));
            }
        }
        const int speaker = speaker_at(frame);
        for (std::size_t k = 0; k < group.size(); k++) {
            Character& c = characters[group[k]];
            c.talking = static_cast<int>(k) == speaker;
            states[group[k]].flags = c.talking ? CG_STATE_TALKING : 0u;
        }
        for (std::size_t i = 0; i < characters.size(); i++) {
            Character& c = characters[i];
            if (c.speed > 0.0f) {
                c.position += osg::Vec3(-std::sin(c.heading), std::cos(c.heading), 0.0f) * (c.speed * dt);
                if (std::fabs(c.position.y()) > c.turn_at) {
                    c.heading = c.heading > kPi / 2 ? 0.0f : kPi;  // turn round
                }
                c.phase += c.speed * dt * 3.2f;
            }
            states[i].position = {c.position.x(), c.position.y(), c.position.z()};
            states[i].heading = c.heading;
            // The animated pose, as the crowd's base pose of the chain (no allocation).
            c.animate();
            rig.base_pose(c.pose, base);
            crowd.set_base_pose(c.id, base);
        }
        crowd.push_frame(frame / kFps, states);
        crowd.step(dt);
        eyelids.resize(characters.size());
        crowd.read_eyelids(0, static_cast<std::uint32_t>(characters.size()), eyelids);
    }
};

// The head in the body's frame: the bone rotations from the head up to the root.
osg::Quat head_in_body(const Character& c) {
    osg::Quat head = to_osg(c.pose[kHead]);
    for (int b = kSkeleton[kHead].parent; b >= 0; b = kSkeleton[b].parent) {
        head = head * to_osg(c.pose[b]);  // OSG's order: the parent's turn last
    }
    return head;
}

// The root's update callback: the crowd is stepped once per frame, before any character
// reads its joints.
class CrowdStepCallback : public osg::NodeCallback {
   public:
    explicit CrowdStepCallback(Street* street) : street_(street) {}
    void operator()(osg::Node* node, osg::NodeVisitor* visitor) override {
        street_->advance();
        traverse(node, visitor);
    }

   private:
    Street* street_;
};

// One per character: writes its place, and its pose with the crowd's gaze in it, into its
// transforms.
class GazeCallback : public osg::NodeCallback {
   public:
    GazeCallback(Street* street, std::size_t character) : street_(street), character_(character) {}
    void operator()(osg::Node* node, osg::NodeVisitor* visitor) override {
        Character& c = street_->characters[character_];
        c.root->setMatrix(osg::Matrix::rotate(c.heading, osg::Z_AXIS) *
                          osg::Matrix::translate(c.position));
        // The crowd's chain joints into the bones' rotations, then every bone's transform.
        street_->crowd.read_joints(c.index, 1, street_->joints);
        street_->rig.write_joints(street_->joints, c.pose);
        for (int b = 0; b < kBones; b++) {
            c.bones[b]->setMatrix(local_matrix(c.pose[b], kSkeleton[b].offset));
        }
        const cg_eyelids& lids = street_->eyelids[c.index];
        c.lid_left->setMatrix(eyelid_matrix(lids.left_lid_pitch, lids.left_closure,
                                            kSkeleton[kLeftEye].offset));
        c.lid_right->setMatrix(eyelid_matrix(lids.right_lid_pitch, lids.right_closure,
                                             kSkeleton[kRightEye].offset));
        if (c.mouth) {  // talking: the mouth opens and closes about four times a second
            const float t = static_cast<float>(street_->frame / kFps);
            const float open = c.talking ? 0.6f + 1.6f * std::fabs(std::sin(12.0f * t)) : 0.3f;
            c.mouth->setMatrix(osg::Matrix::scale(1.0f, 1.0f, open) * osg::Matrix::translate(kMouth));
            c.talk_marker->setNodeMask(c.talking ? ~0u : 0u);
        }
        traverse(node, visitor);
    }

   private:
    Street* street_;
    std::size_t character_;
};

// The figure of one character: one transform per bone of kSkeleton, at rest, under its
// parent's (the root bone under the character's), each with its part of the body.
void build_figure(Character& c, const osg::Vec4& shirt, const osg::Vec4& trousers, bool red_nose,
                  bool talker) {
    const osg::Vec4 skin(0.93f, 0.76f, 0.62f, 1.0f);
    const osg::Vec4 hair(0.22f, 0.15f, 0.10f, 1.0f);
    const osg::Vec4 eye_white(0.97f, 0.97f, 0.95f, 1.0f);
    const osg::Vec4 pupil(0.05f, 0.05f, 0.08f, 1.0f);
    // A torso slab from `z` up 0.1 in a spine bone's frame.
    const auto slab = [&](float z, float width) {
        return box({0.0f, 0.0f, z + 0.05f}, {width, 0.22f, 0.1f}, shirt);
    };
    c.root = new osg::MatrixTransform;
    c.pose.fill(cg_quat{0.0f, 0.0f, 0.0f, 1.0f});
    for (int b = 0; b < kBones; b++) {
        osg::ref_ptr<osg::MatrixTransform> bone =
            new osg::MatrixTransform(local_matrix(c.pose[b], kSkeleton[b].offset));
        bone->setName(kSkeleton[b].name);
        c.bones[b] = bone;
        const int parent = kSkeleton[b].parent;
        (parent < 0 ? c.root.get() : c.bones[parent].get())->addChild(bone);
        switch (b) {
            case kHips:  // the pelvis
                bone->addChild(box({0.0f, 0.0f, 0.0f}, {0.34f, 0.2f, 0.12f}, trousers));
                break;
            case kSpine:  // the torso, 0.1 slabs from 1.00 to 1.50, the shoulders widest
                bone->addChild(slab(0.0f, 0.36f));
                bone->addChild(slab(0.1f, 0.38f));
                break;
            case kSpine1:
                bone->addChild(slab(0.0f, 0.40f));
                bone->addChild(slab(0.1f, 0.42f));
                break;
            case kSpine2:
                bone->addChild(slab(0.0f, 0.46f));
                break;
            case kNeck:
                bone->addChild(cylinder({0.0f, 0.0f, 0.03f}, 0.05f, 0.07f, skin));
                bone->addChild(cylinder({0.0f, 0.0f, 0.08f}, 0.05f, 0.07f, skin));
                break;
            case kHead: {
                bone->addChild(sphere({0.0f, -0.01f, 0.1f}, 0.1f, skin));
                bone->addChild(sphere({0.0f, -0.035f, 0.125f}, 0.1f, hair));
                osg::ref_ptr<osg::Geode> nose =
                    red_nose ? sphere(kNose, 0.03f, osg::Vec4(1.0f, 0.0f, 0.0f, 1.0f))
                             : box(kNose, {0.03f, 0.05f, 0.04f}, skin);
                if (red_nose) {  // a clown's nose, unlit: exactly (255, 0, 0) on the image
                    nose->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
                }
                bone->addChild(nose);
                break;
            }
            case kLeftEye:
            case kRightEye:  // a white ball, a dark pupil along the eye's forward (+Y)
                bone->addChild(sphere({0.0f, 0.0f, 0.0f}, 0.022f, eye_white));
                bone->addChild(sphere({0.0f, 0.016f, 0.0f}, 0.011f, pupil));
                break;
            case kLeftArm:
            case kRightArm:  // swinging from the shoulder
                bone->addChild(box({0.0f, 0.0f, -0.3f}, {0.08f, 0.09f, 0.6f}, shirt));
                bone->addChild(sphere({0.0f, 0.0f, -0.62f}, 0.045f, skin));
                break;
            default:  // the legs, swinging from the hip joint
                bone->addChild(box({0.0f, 0.0f, -0.45f}, {0.13f, 0.15f, 0.9f}, trousers));
                break;
        }
    }
    // The upper eyelids, open, under the head at the eye bones' places (the eyes turn inside
    // them).
    const osg::Vec4 lid_skin(0.86f, 0.66f, 0.52f, 1.0f);
    const auto lid_over = [&](Bone eye) {
        osg::ref_ptr<osg::MatrixTransform> lid =
            new osg::MatrixTransform(eyelid_matrix(0.0f, 0.0f, kSkeleton[eye].offset));
        lid->addChild(eyelid_shell(kLidRadius, lid_skin));
        c.bones[kSkeleton[eye].parent]->addChild(lid);
        return lid;
    };
    c.lid_left = lid_over(kLeftEye);
    c.lid_right = lid_over(kRightEye);
    if (talker) {
        // A dark mouth under the nose (scaled open while talking), and a yellow marker above
        // the head shown while talking (unlit, so it reads from afar).
        c.mouth = new osg::MatrixTransform(osg::Matrix::scale(1.0f, 1.0f, 0.3f) *
                                           osg::Matrix::translate(kMouth));
        c.mouth->addChild(box({0.0f, 0.0f, 0.0f}, {0.06f, 0.024f, 0.016f}, {0.35f, 0.08f, 0.1f, 1.0f}));
        c.bones[kHead]->addChild(c.mouth);
        osg::ref_ptr<osg::Geode> marker = sphere({0.0f, -0.02f, 0.42f}, 0.06f, {1.0f, 0.85f, 0.1f, 1.0f});
        marker->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
        marker->setNodeMask(0u);
        c.talk_marker = marker;
        c.bones[kHead]->addChild(marker);
    }
}

osg::ref_ptr<osg::Group> build_street_set(const std::vector<osg::Vec3>& lamps) {
    osg::ref_ptr<osg::Group> set = new osg::Group;
    set->addChild(box({0.0f, 0.0f, -0.05f}, {14.0f, 60.0f, 0.1f}, {0.62f, 0.6f, 0.57f, 1.0f}));
    set->addChild(box({0.0f, 0.0f, -0.03f}, {4.0f, 60.0f, 0.08f}, {0.48f, 0.47f, 0.46f, 1.0f}));
    for (int side = -1; side <= 1; side += 2) {
        const float x = 7.0f * static_cast<float>(side);
        for (int block = 0; block < 6; block++) {
            const float y = -25.0f + 10.0f * static_cast<float>(block);
            const float height = 7.0f + 2.0f * static_cast<float>((block * 7 + side + 3) % 3);
            const osg::Vec4 wall = block % 2 == 0 ? osg::Vec4(0.80f, 0.72f, 0.58f, 1.0f)
                                                  : osg::Vec4(0.66f, 0.70f, 0.74f, 1.0f);
            set->addChild(box({x + 0.5f * static_cast<float>(side), y, height / 2}, {1.0f, 9.6f, height}, wall));
            // A shop window and two rows of windows.
            set->addChild(box({x, y, 1.4f}, {0.1f, 5.0f, 1.8f}, {0.25f, 0.35f, 0.42f, 1.0f}));
            for (int row = 0; row < 2; row++) {
                for (int w = -1; w <= 1; w++) {
                    set->addChild(box({x, y + 2.8f * static_cast<float>(w), 3.8f + 2.2f * static_cast<float>(row)},
                                      {0.1f, 1.2f, 1.3f}, {0.2f, 0.27f, 0.33f, 1.0f}));
                }
            }
        }
    }
    for (const osg::Vec3& lamp : lamps) {
        set->addChild(cylinder(lamp + osg::Vec3(0.0f, 0.0f, 1.75f), 0.06f, 3.5f, {0.18f, 0.2f, 0.2f, 1.0f}));
        set->addChild(sphere(lamp + osg::Vec3(0.0f, 0.0f, 3.6f), 0.2f, {0.98f, 0.92f, 0.6f, 1.0f}));
    }
    return set;
}

// Captures the colour buffer of the frames it is armed for, after they are drawn.
class Capture : public osg::Camera::DrawCallback {
   public:
    Capture(int width, int height) : width_(width), height_(height) {}
    void arm(const std::string& path) { path_ = path; }
    bool written() const { return written_; }
    void operator()(osg::RenderInfo&) const override {
        if (path_.empty()) return;
        osg::ref_ptr<osg::Image> image = new osg::Image;
        image->readPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE);
        written_ = osgDB::writeImageFile(*image, path_);
        path_.clear();
    }

   private:
    int width_, height_;
    mutable std::string path_;
    mutable bool written_ = false;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: osg_street OUTDIR [WIDTHxHEIGHT] [SECONDS]\n");
        return 2;
    }
    const std::string out_dir = argv[1];
    int width = 960, height = 540;
    if (argc > 2 && std::sscanf(argv[2], "%dx%d", &width, &height) != 2) {
        std::fprintf(stderr, "bad size %s\n", argv[2]);
        return 2;
    }
    const double seconds = argc > 3 ? std::atof(argv[3]) : 8.0;
    std::printf("OpenSceneGraph %s, crowdgaze %s\n", osgGetVersion(), crowdgaze::version_string());

    try {
        // --- the crowd: Z up, heading 0 along +Y, metres ----------------------------------
        Street street;
        const char* scene = std::getenv("OSG_STREET_SCENE");
        const bool look_up = scene != nullptr && std::string(scene) == "look-up";
        cg_crowd_config config = crowdgaze::crowd_config();
        // The look-up scene: passers-by may follow the group's gaze (docs/street.md).
        config.follow_enabled = look_up ? 1u : 0u;
        config.seed = 2009;
        config.max_characters = 32;
        config.max_objects = 32;
        config.up_axis = CG_AXIS_POSITIVE_Z;
        config.forward_axis = CG_AXIS_POSITIVE_Y;
        if (const char* rate = std::getenv("OSG_STREET_BLINK_RATE")) {
            config.blink_rate = static_cast<float>(std::atof(rate));
        }
        street.crowd = crowdgaze::Crowd(config);

        // --- the skeleton, mapped once to a gaze chain in the crowd's axes and units ------
        std::array<const char*, kBones> names{};
        std::array<std::int32_t, kBones> parents{};
        std::array<cg_vec3, kBones> offsets{};
        for (int b = 0; b < kBones; b++) {
            names[b] = kSkeleton[b].name;
            parents[b] = kSkeleton[b].parent;
            offsets[b] = kSkeleton[b].offset;
        }
        cg_rig_desc rig_desc = crowdgaze::rig_desc();  // up and forward detected, metres
        rig_desc.bone_count = kBones;
        rig_desc.bone_names = names.data();
        rig_desc.parents = parents.data();
        rig_desc.rest_translations = offsets.data();
        crowdgaze::set_rig_crowd(rig_desc, config);
        street.rig = crowdgaze::Rig(rig_desc);
        const std::string report = street.rig.report();
        std::printf("%s\n", report.substr(0, report.find('\n')).c_str());
        street.chain = street.rig.chain();
        street.base.resize(street.rig.joint_count());
        street.joints.resize(street.rig.joint_count());
        // The chain's head bone (then the two eyes) must be the one the figure's head is on.
        const std::vector<std::uint32_t> chain_bones = street.rig.chain_bones();
        if (chain_bones.size() < 3 || chain_bones[chain_bones.size() - 3] != kHead ||
            chain_bones.back() != kRightEye) {
            std::fprintf(stderr, "unexpected mapping:\n%s", report.c_str());
            return 1;
        }

        std::vector<osg::Vec3> lamps;
        for (int i = 0; i < 6; i++) {
            const float side = i % 2 == 0 ? -5.2f : 5.2f;
            lamps.emplace_back(side, -20.0f + 8.0f * static_cast<float>(i), 0.0f);
        }
        for (const osg::Vec3& lamp : lamps) {
            cg_object_desc object = crowdgaze::object_desc();
            object.position = {lamp.x(), lamp.y(), 0.0f};
            object.look_at_height = 3.6f;
            object.impact = 0.6f;
            street.crowd.add_object(object);
        }
        for (int i = 0; i < 8; i++) {  // shop windows
            cg_object_desc object = crowdgaze::object_desc();
            const float side = i % 2 == 0 ? -1.0f : 1.0f;
            object.position = {6.9f * side, -25.0f + 10.0f * static_cast<float>(i / 2 + 1), 0.0f};
            object.heading = side * kPi / 2;  // facing the street
            object.look_at_height = 1.4f;
            object.impact = 0.8f;
            street.crowd.add_object(object);
        }

        const osg::Vec4 shirts[] = {{0.20f, 0.35f, 0.70f, 1}, {0.25f, 0.55f, 0.30f, 1},
                                    {0.85f, 0.70f, 0.20f, 1}, {0.50f, 0.30f, 0.60f, 1},
                                    {0.15f, 0.55f, 0.60f, 1}, {0.90f, 0.90f, 0.88f, 1},
                                    {0.45f, 0.32f, 0.22f, 1}, {0.30f, 0.30f, 0.35f, 1}};
        const osg::Vec4 trousers[] = {{0.15f, 0.17f, 0.25f, 1}, {0.30f, 0.27f, 0.22f, 1},
                                      {0.12f, 0.12f, 0.12f, 1}, {0.40f, 0.42f, 0.45f, 1}};
        // Walkers: x, y, heading (0 up the street, pi down), speed. The first one passes in
        // front of the red-nosed bystander.
        struct Walk { float x, y, heading, speed; };
        const Walk walks[] = {{1.2f, -19.0f, 0.0f, 1.2f},   {-1.0f, 6.0f, kPi, 1.25f},
                              {2.4f, 12.0f, kPi, 1.4f},    {-2.6f, -10.0f, 0.0f, 1.2f},
                              {0.2f, 17.0f, kPi, 1.3f},    {-0.4f, -4.0f, 0.0f, 1.15f},
                              {3.4f, 2.0f, kPi, 1.45f},    {-3.3f, 9.0f, 0.0f, 1.3f},
                              {0.9f, -7.0f, 0.0f, 1.5f},   {-1.8f, 15.0f, kPi, 1.2f},
                              {2.0f, -1.0f, 0.0f, 1.1f},   {-2.2f, 1.0f, kPi, 1.35f}};
        // Bystanders: x, y, heading (facing the street); the first one has the red nose.
        const Walk stands[] = {{2.6f, -14.5f, 2.11f, 0.0f}, {-4.0f, -8.0f, -kPi / 2, 0.0f},
                               {4.3f, 0.0f, kPi / 2 + 0.3f, 0.0f}};
        // The group: three friends round a point of the right pavement, facing its centre
        // (heading 0 along +Y, counter-clockwise: the direction (dx, dy) is atan2(-dx, dy)).
        const osg::Vec3 meeting(4.2f, -10.5f, 0.0f);
        std::vector<Walk> friends;
        for (const float degrees : {60.0f, 180.0f, 300.0f}) {
            const float angle = degrees * kPi / 180.0f;
            const osg::Vec3 at = meeting + osg::Vec3(std::cos(angle), std::sin(angle), 0.0f) * 0.62f;
            const osg::Vec3 to_centre = meeting - at;
            friends.push_back({at.x(), at.y(), std::atan2(-to_centre.x(), to_centre.y()), 0.0f});
        }

        osg::ref_ptr<osg::Group> root = new osg::Group;
        root->addChild(build_street_set(lamps));
        std::size_t n = 0;
        const auto add = [&](const Walk& w, bool red_nose, bool talker) {
            Character c;
            c.position.set(w.x, w.y, 0.0f);
            c.heading = w.heading;
            c.speed = w.speed;
            cg_character_desc desc = crowdgaze::character_desc({w.x, w.y, 0.0f}, w.heading);
            desc.chain = &street.chain;
            c.id = street.crowd.add_character(desc);
            c.index = static_cast<std::uint32_t>(n);
            build_figure(c, shirts[n % 8], trousers[n % 4], red_nose, talker);
            cg_entity_state state = crowdgaze::entity_state();  // explicit headings
            state.id = c.id;
            street.states.push_back(state);
            street.characters.push_back(c);
            n++;
        };
        for (const Walk& w : walks) add(w, false, false);
        street.observer = n;
        for (const Walk& s : stands) add(s, n == street.observer, false);
        std::vector<std::uint32_t> members;
        for (const Walk& f : friends) {
            street.group.push_back(n);
            add(f, false, true);
            members.push_back(street.characters.back().id);
        }
        // The friends are one conversation.
        street.conversation = street.crowd.set_conversation(members);
        std::printf("group %u of %zu:", street.conversation, members.size());
        for (const std::size_t i : street.group) std::printf(" %zu (id %u)", i, street.characters[i].id);
        std::printf("\n");
        // The red-nosed bystander follows the first walker with its eyes and head as it
        // passes; the others look where crowdgaze's attention model takes them.
        street.observed_walker = street.characters[0].id;
        street.crowd.set_gaze_target(street.characters[street.observer].id,
                                     crowdgaze::gaze_target_entity(street.observed_walker));

        std::printf("observer %zu follows %u\n", street.observer, street.characters[0].index);
        // The look-up scene: four people on the left pavement, turned towards the facade
        // across the street; at kLookFrame they stare at kLookPoint (Street::advance).
        if (look_up) {
            const osg::Vec3 point(kLookPoint.x, kLookPoint.y, kLookPoint.z);
            osg::ref_ptr<osg::Geode> mark = sphere(point, 0.25f, {1.0f, 0.55f, 0.0f, 1.0f});
            mark->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
            root->addChild(mark);  // unlit: exactly (255, 140, 0) on the image
            std::printf("lookers");
            for (const osg::Vec3& at : {osg::Vec3(-4.7f, -13.0f, 0.0f), osg::Vec3(-4.0f, -12.3f, 0.0f),
                                        osg::Vec3(-4.8f, -11.5f, 0.0f), osg::Vec3(-4.1f, -10.8f, 0.0f)}) {
                const osg::Vec3 to_point = point - at;
                street.lookers.push_back(n);
                std::printf(" %zu", n);
                add({at.x(), at.y(), std::atan2(-to_point.x(), to_point.y()), 0.0f}, false, false);
            }
            std::printf("\nlook point %.2f %.2f %.2f from frame %d\n", kLookPoint.x, kLookPoint.y,
                        kLookPoint.z, kLookFrame);
        }
        for (std::size_t i = 0; i < street.characters.size(); i++) {
            Character& c = street.characters[i];
            c.root->setUpdateCallback(new GazeCallback(&street, i));
            root->addChild(c.root);
        }
        root->setUpdateCallback(new CrowdStepCallback(&street));
        osg::ref_ptr<osg::Material> material = new osg::Material;
        material->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
        root->getOrCreateStateSet()->setAttributeAndModes(material);

        // --- offscreen rendering ----------------------------------------------------------
        osgViewer::Viewer viewer;
        viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
        viewer.setSceneData(root);
        viewer.setLightingMode(osg::View::SKY_LIGHT);
        viewer.getLight()->setPosition(osg::Vec4(0.4f, -0.5f, 1.0f, 0.0f));
        viewer.getLight()->setAmbient(osg::Vec4(0.45f, 0.45f, 0.45f, 1.0f));
        viewer.getLight()->setDiffuse(osg::Vec4(0.75f, 0.75f, 0.72f, 1.0f));

        osg::ref_ptr<osg::GraphicsContext::Traits> traits = new osg::GraphicsContext::Traits;
        traits->readDISPLAY();  // the X display from $DISPLAY (xvfb-run sets it)
        traits->setUndefinedScreenDetailsToDefaultScreen();
        traits->width = width;
        traits->height = height;
        traits->red = traits->green = traits->blue = 8;
        traits->alpha = 8;
        traits->depth = 24;
        traits->windowDecoration = false;
        // A window on the (virtual, Xvfb) X display, drawn double-buffered and read back
        // before the swap; OSG_STREET_SURFACE=pbuffer asks for a single-buffered GLX pbuffer
        // instead (it renders too, but Xvfb's GLX answers each frame with a BadMatch that
        // OSG prints).
        const char* wanted = std::getenv("OSG_STREET_SURFACE");
        traits->pbuffer = wanted != nullptr && std::string(wanted) == "pbuffer";
        traits->doubleBuffer = !traits->pbuffer;
        osg::ref_ptr<osg::GraphicsContext> context =
            osg::GraphicsContext::createGraphicsContext(traits.get());
        const char* surface = traits->pbuffer ? "pbuffer" : "window";
        if (!context || !context->valid()) {
            std::fprintf(stderr, "no OpenGL context: is DISPLAY set (run under xvfb-run)?\n");
            return 1;
        }
        std::printf("rendering %dx%d into a %s\n", width, height, surface);
        osg::Camera* camera = viewer.getCamera();
        camera->setGraphicsContext(context.get());
        camera->setViewport(new osg::Viewport(0, 0, width, height));
        const GLenum buffer = traits->doubleBuffer ? GL_BACK : GL_FRONT;
        camera->setDrawBuffer(buffer);
        camera->setReadBuffer(buffer);
        camera->setClearColor(osg::Vec4(0.62f, 0.76f, 0.90f, 1.0f));
        camera->setProjectionMatrixAsPerspective(42.0, static_cast<double>(width) / height, 0.3, 200.0);
        if (look_up) {  // wider, the lookers from their right and the point above the street
            camera->setProjectionMatrixAsPerspective(60.0, static_cast<double>(width) / height, 0.3, 200.0);
            camera->setViewMatrixAsLookAt(osg::Vec3d(-1.0, -20.0, 1.5), osg::Vec3d(0.2, -12.0, 3.8),
                                          osg::Vec3d(0.0, 0.0, 1.0));
        } else {
            camera->setViewMatrixAsLookAt(osg::Vec3d(-1.0, -18.5, 2.2), osg::Vec3d(1.6, -9.0, 1.4),
                                          osg::Vec3d(0.0, 0.0, 1.0));
        }
        osg::ref_ptr<Capture> capture = new Capture(width, height);
        camera->setFinalDrawCallback(capture.get());
        viewer.realize();

        // --- the frames -------------------------------------------------------------------
        const int frames = static_cast<int>(seconds * kFps + 0.5);
        const int every = static_cast<int>(kFps);  // one PNG per second
        int written = 0;
        for (int frame = 1; frame <= frames; frame++) {
            char path[512] = "";
            if (frame % every == 0) {
                std::snprintf(path, sizeof path, "%s/frame_%04d.png", out_dir.c_str(), frame);
                capture->arm(path);
            }
            viewer.frame(frame / kFps);
            if (path[0] == '\0') continue;
            if (!capture->written()) {
                std::fprintf(stderr, "could not write %s\n", path);
                return 1;
            }
            written++;
            std::printf("frame %d t %.3f png %s\n", frame, frame / kFps, path);
            std::vector<cg_gaze_info> gaze(n);
            street.crowd.read_gaze(gaze);
            for (std::size_t i = 0; i < n; i++) {
                const cg_eyelids& lids = street.eyelids[i];
                std::printf("lids %zu closure %.3f %.3f pitch %.4f %.4f\n", i, lids.left_closure,
                            lids.right_closure, lids.left_lid_pitch, lids.right_lid_pitch);
            }
            for (std::size_t i = 0; i < n; i++) {
                const osg::Quat head = head_in_body(street.characters[i]);
                std::printf("head %zu q %.5f %.5f %.5f %.5f yaw %.2f target %d\n", i, head.x(),
                            head.y(), head.z(), head.w(), yaw_degrees(head),
                            gaze[i].target == CG_NO_TARGET ? -1 : static_cast<int>(gaze[i].target));
            }
            for (const std::size_t i : street.lookers) {
                // The head's pitch in the body frame: its forward (+Y) turned up (+Z).
                const osg::Vec3d forward = head_in_body(street.characters[i]) * osg::Vec3d(0.0, 1.0, 0.0);
                const double pitch =
                    std::atan2(forward.z(), std::hypot(forward.x(), forward.y())) * 180.0 / kPi;
                std::printf("look %zu pitch %.2f staring %d\n", i, pitch, frame >= kLookFrame ? 1 : 0);
            }
            if (look_up) {  // who glances where the group looks, now and so far
                std::uint32_t now = 0, glanced = 0;
                for (const Character& c : street.characters) {
                    const crowdgaze::Crowd::Following f = street.crowd.following(c.id);
                    const float dx = f.point.x - kLookPoint.x, dy = f.point.y - kLookPoint.y,
                                dz = f.point.z - kLookPoint.z;
                    now += f.following && dx * dx + dy * dy + dz * dz < 0.01f ? 1u : 0u;
                    glanced += f.glances > 0 ? 1u : 0u;
                }
                std::printf("followers %u at the point now, %u glanced so far\n", now, glanced);
            }
            // Where the red nose is on the image (x from the left, y from the top): the head
            // bone's transform and its ancestors', then the character's place.
            const Character& o = street.characters[street.observer];
            osg::Matrix world = o.bones[kHead]->getMatrix();
            for (int b = kSkeleton[kHead].parent; b >= 0; b = kSkeleton[b].parent) {
                world = world * o.bones[b]->getMatrix();
            }
            world = world * o.root->getMatrix();
            const osg::Matrix to_window = camera->getViewMatrix() * camera->getProjectionMatrix() *
                                          camera->getViewport()->computeWindowMatrix();
            const osg::Vec3 nose = kNose * world * to_window;
            std::printf("nose %.1f %.1f\n", nose.x(), height - nose.y());
            // The group: who talks, and what each member looks at (a member's id, another
            // entity's, or -1 ahead or away).
            const int speaker = street.speaker_at(frame);
            for (std::size_t k = 0; k < street.group.size(); k++) {
                const std::size_t i = street.group[k];
                const std::uint32_t target = gaze[i].target;
                const char* at = target == CG_NO_TARGET ? "away" : "other";
                for (std::size_t m = 0; m < street.group.size(); m++) {
                    if (m != k && target == street.characters[street.group[m]].id) {
                        at = static_cast<int>(m) == speaker ? "speaker" : "member";
                    }
                }
                std::printf("talk %zu id %u group %u talking %d target %d at %s\n", i,
                            street.characters[i].id,
                            street.crowd.conversation(street.characters[i].id),
                            street.characters[i].talking ? 1 : 0,
                            target == CG_NO_TARGET ? -1 : static_cast<int>(target), at);
            }
        }
        std::printf("frames written: %d\n", written);
        if (written == 0) return 1;
    } catch (const crowdgaze::Error& error) {
        std::fprintf(stderr, "crowdgaze: %s\n", error.what());
        return 1;
    }
    std::printf("ok\n");
    return 0;
}
