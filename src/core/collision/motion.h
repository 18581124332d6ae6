// Keyed rigid motion (MotionDef): the pose of a moving collider or pin at a time.
#pragma once

#include "drape/collider.h"
#include "drape/scene.h"

namespace drape {

/// The rotation of `degrees` about x, then y, then z (as MeshTransform and box.rotate).
Mat3 rotation_xyz(const Vec3& degrees);

/// The pose of a body moved by `motion` at time t (s): translation linear and rotation a slerp
/// between the keys around t, held before the first key and after the last (or repeated, with
/// `loop`), the rotation about motion.pivot or else `reference`. Identity without keys.
Pose pose_at(const MotionDef& motion, const Vec3& reference, double t);

/// The motion's time folded into the keys' span when it loops.
double motion_time(const MotionDef& motion, double t);

}  // namespace drape
