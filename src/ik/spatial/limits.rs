//! Joint limits per lane: twist about an axis and a swing cone
//! ([`crate::ik::JointLimits`]) as the cosines and sines of their half-angles, clamping a
//! rotation into them, and turning a joint by a world rotation within them.

use glam::Vec3;

use super::turn::Turn;
use crate::ik::chain::{GazeChain, JointLimits, CLAMP_SLACK};
use crate::math::lanes::{Floats, Mask, MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

/// Per lane, a joint's limits.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits<W> {
    axis: V3<W>,
    min_cos: Floats<W>,
    min_sin: Floats<W>,
    max_cos: Floats<W>,
    max_sin: Floats<W>,
    cone_cos: Floats<W>,
    cone_sin: Floats<W>,
}

impl<W: Wide> Limits<W> {
    /// The same limits in every lane.
    #[inline(always)]
    pub(crate) fn splat(limits: &JointLimits) -> Limits<W> {
        let (cone, min, max) = limits.half_angles();
        Limits {
            axis: V3::splat(limits.twist_axis().into()),
            min_cos: Floats::splat(min.0),
            min_sin: Floats::splat(min.1),
            max_cos: Floats::splat(max.0),
            max_sin: Floats::splat(max.1),
            cone_cos: Floats::splat(cone.0),
            cone_sin: Floats::splat(cone.1),
        }
    }

    /// Each lane's limits of joint `indices[lane]` (free past the lane's joints).
    #[inline(always)]
    pub(crate) fn of_joints(
        chains: &[&GazeChain; MAX_LANES],
        same_chain: bool,
        indices: [usize; MAX_LANES],
    ) -> Limits<W> {
        let uniform = indices.iter().all(|index| *index == indices[0]);
        if same_chain && uniform {
            if let Some(joint) = chains[0].joints().get(indices[0]) {
                return Limits::splat(&joint.limits);
            }
        }
        Limits::gather(|i| match chains[i].joints().get(indices[i]) {
            Some(joint) => joint.limits,
            None => JointLimits::free(Vec3::Y),
        })
    }

    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> JointLimits) -> Limits<W> {
        // Rows: the twist axis's x, y, z, then the cosine and sine of the half angles of
        // the twist minimum, the twist maximum and the cone.
        let mut rows = [[0.0; MAX_LANES]; 9];
        for i in 0..W::LANES {
            let limits = f(i);
            let axis = limits.twist_axis();
            let (cone, min, max) = limits.half_angles();
            let column = [
                axis.x, axis.y, axis.z, min.0, min.1, max.0, max.1, cone.0, cone.1,
            ];
            for (row, value) in rows.iter_mut().zip(column) {
                row[i] = value;
            }
        }
        Limits {
            axis: V3 {
                x: Floats::load(&rows[0]),
                y: Floats::load(&rows[1]),
                z: Floats::load(&rows[2]),
            },
            min_cos: Floats::load(&rows[3]),
            min_sin: Floats::load(&rows[4]),
            max_cos: Floats::load(&rows[5]),
            max_sin: Floats::load(&rows[6]),
            cone_cos: Floats::load(&rows[7]),
            cone_sin: Floats::load(&rows[8]),
        }
    }

    /// Per lane, [`JointLimits::clamp`]: the rotation within the limits nearest to
    /// `rotation`, and where it is `rotation` itself, unchanged.
    #[inline(always)]
    pub(crate) fn clamp(&self, rotation: Q4<W>) -> (Q4<W>, Mask<W>) {
        let projection = rotation.vector().dot(self.axis);
        let w = rotation.w;
        // With a slack of CLAMP_SLACK, so that a rotation clamped before counts as inside.
        let slack = Floats::splat(-CLAMP_SLACK);
        let twist_inside = (self.min_cos * projection - self.min_sin * w).cmpge(slack)
            & (w * self.max_sin - projection * self.max_cos).cmpge(slack);
        let twist_length_squared = w * w + projection * projection;
        let swing_inside = twist_length_squared.cmpge(self.cone_cos * self.cone_cos + slack);
        let inside = twist_inside & swing_inside;
        if inside.all() {
            return (rotation, inside);
        }
        let length = twist_length_squared.sqrt();
        let degenerate = length.cmplt(Floats::splat(1e-9));
        let inverse = length.recip();
        let twist_cos = Floats::select(degenerate, Floats::one(), w * inverse);
        let twist_sin = Floats::select(degenerate, Floats::zero(), projection * inverse);
        let twist = Q4::from_parts(self.axis.scale(twist_sin), twist_cos);
        let swing = rotation.mul(twist.conjugate());
        let to_min = twist_cos * self.min_cos + twist_sin * self.min_sin;
        let to_max = twist_cos * self.max_cos + twist_sin * self.max_sin;
        let nearer_min = to_min.cmpgt(to_max);
        let twist_cos = Floats::select(
            twist_inside,
            twist_cos,
            Floats::select(nearer_min, self.min_cos, self.max_cos),
        );
        let twist_sin = Floats::select(
            twist_inside,
            twist_sin,
            Floats::select(nearer_min, self.min_sin, self.max_sin),
        );
        // The swing's scalar part is the twist's length (see above): the swing is out of its
        // cone where the fast test said so.
        let swing = if swing_inside.all() {
            swing
        } else {
            let swing_vector = swing.vector();
            let swing_sin = swing_vector.length_squared().sqrt();
            let clamped_swing = Q4::select(
                swing_sin.cmpgt(Floats::splat(1e-9)),
                Q4::from_parts(swing_vector.scale(self.cone_sin / swing_sin), self.cone_cos),
                Q4::identity(),
            );
            Q4::select(swing_inside, swing, clamped_swing)
        };
        // Both factors are unit quaternions: so is their product.
        let clamped = swing.mul(Q4::from_parts(self.axis.scale(twist_sin), twist_cos));
        (Q4::select(inside, rotation, clamped), inside)
    }
}

/// Per lane, turns a joint whose pre-delta world rotation is `joint_rotation` by the world
/// rotation `turn`, within its limits: returns the local delta and the world rotation it
/// makes.
#[inline(always)]
pub(super) fn turn_joint<W: Wide>(
    limits: &Limits<W>,
    joint_rotation: Q4<W>,
    turn: Turn<W>,
) -> (Q4<W>, Q4<W>) {
    let local_axis = joint_rotation.conjugate().rotate(turn.axis);
    let wanted = Q4::from_parts(local_axis.scale(turn.sin), turn.cos);
    let (delta, unchanged) = limits.clamp(wanted);
    let world = Q4::from_parts(turn.axis.scale(turn.sin), turn.cos);
    if unchanged.all() {
        return (delta, world);
    }
    // jr · delta · jr⁻¹: the delta's vector part seen in the world.
    let clamped_world = Q4::from_parts(joint_rotation.rotate(delta.vector()), delta.w);
    (delta, Q4::select(unchanged, world, clamped_world))
}
