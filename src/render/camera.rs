//! Pinhole (perspective) and orthographic cameras set up by look-at, and automatic framing of a
//! bounding box.

use glam::DVec3;

use crate::error::{Error, Problem, Result};
use crate::geom::Aabb;
use crate::render::intersect::Ray64;

/// Points a camera keeps in view (automatic framing): their box, and the largest value over
/// them of a convex function (the distance at which a point comes into view).
///
/// A plain slice of points is one; [`crate::render::job::SurfaceSamples`] is another that
/// never stores its points. Both give the same numbers as one pass over the points in any
/// order: a box and a maximum do not depend on the order.
pub trait FramedPoints: Sync {
    /// The box of the points.
    fn bounds(&self) -> Aabb;
    /// `max(floor, f(p))` over the points `p`, for a convex `f` whose rounding error at any
    /// point is below `margin` (a point set may skip points whose convex hull provably stays
    /// below the maximum).
    fn max_convex(&self, f: &(dyn Fn(DVec3) -> f64 + Sync), floor: f64, margin: f64) -> f64;
}

impl FramedPoints for [DVec3] {
    fn bounds(&self) -> Aabb {
        Aabb::from_points(self)
    }

    fn max_convex(&self, f: &(dyn Fn(DVec3) -> f64 + Sync), floor: f64, _margin: f64) -> f64 {
        self.iter().fold(floor, |m, &p| m.max(f(p)))
    }
}

/// Automatic framing leaves this factor of room around the framed points: their extent is at
/// most `1/FRAMING_MARGIN` of the half-image on the axis that sets the distance, so each
/// margin is `(1 − 1/FRAMING_MARGIN)/2` ≈ 4.5 % of the image there.
pub(crate) const FRAMING_MARGIN: f64 = 1.1;

/// How the image plane maps to rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Rays from the eye; `fov_deg` is the vertical field of view.
    Perspective {
        /// Vertical field of view in degrees.
        fov_deg: f64,
    },
    /// Parallel rays along the view direction; `height` is the world height of the image.
    Orthographic {
        /// World-space height of the view.
        height: f64,
    },
}

/// The smallest vertical field of view, degrees. Automatic framing puts the eye at about
/// `diagonal / fov` from the surface (6·10^4 diagonals at 10^-3°), and the f32 BVH traversal
/// loses hits when the eye is much farther (measured on the bunny: all hits at 10^-3°, 12 %
/// lost at 10^-4°, all at 10^-6°).
pub(crate) const MIN_FOV_DEG: f64 = 1e-3;

/// Checks a vertical field of view: in [[`MIN_FOV_DEG`], 180°).
fn check_fov(fov_deg: f64) -> Result<()> {
    if (MIN_FOV_DEG..180.0).contains(&fov_deg) {
        Ok(())
    } else {
        Err(Error::config(
            "field of view",
            Problem::Must {
                value: format!("{}°", short(fov_deg)),
                requirement: format!("be at least {MIN_FOV_DEG}° and below 180°"),
            },
        ))
    }
}

/// `x` for a message: plain for ordinary magnitudes, in exponent notation otherwise (so that
/// 1e-300 is not printed with 300 digits).
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The unit vector along `v`, or None if `v` is zero or not finite. Scaled by its largest
/// component first, so that neither `|v|²` overflows (|v| ≈ 1e300) nor underflows (1e-300).
pub(crate) fn unit(v: DVec3) -> Option<DVec3> {
    let scale = v.abs().max_element();
    (scale > 0.0 && scale.is_finite()).then(|| (v / scale).normalize())
}

/// The unit direction from `from` to `to`, or None if they coincide. Both points are scaled by
/// their largest coordinate before the difference is taken, so that it cannot overflow (eye at
/// 1e300, target at −1e300) and the result does not depend on the scale of the scene.
pub(crate) fn unit_direction(from: DVec3, to: DVec3) -> Option<DVec3> {
    let scale = from.abs().max_element().max(to.abs().max_element());
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    unit(to / scale - from / scale)
}

/// The distance between `a` and `b`, without overflow in the squares (see [`unit_direction`]).
fn distance(a: DVec3, b: DVec3) -> f64 {
    let scale = a.abs().max_element().max(b.abs().max_element());
    if scale > 0.0 {
        (b / scale - a / scale).length() * scale
    } else {
        0.0
    }
}

/// A look-at camera with an orthonormal frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Point looked at.
    pub target: DVec3,
    /// Projection.
    pub projection: Projection,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
}

/// The rays of one image through a [`Camera`] ([`Camera::rays`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CameraRays<'c> {
    camera: &'c Camera,
    aspect: f64,
    /// `tan(fov / 2)` of a perspective projection.
    tan: f64,
}

impl CameraRays<'_> {
    /// The ray through image-plane point `(x, y)`, both in `[-1, 1]` (x right, y up).
    pub(crate) fn at(&self, x: f64, y: f64) -> Ray64 {
        let camera = self.camera;
        match camera.projection {
            Projection::Perspective { .. } => {
                let (tan, aspect) = (self.tan, self.aspect);
                let dir =
                    camera.forward + camera.right * (x * tan * aspect) + camera.up * (y * tan);
                Ray64::new(camera.eye, dir)
            }
            Projection::Orthographic { height } => {
                let origin = camera.eye
                    + camera.right * (0.5 * x * height * self.aspect)
                    + camera.up * (0.5 * y * height);
                Ray64 {
                    origin,
                    dir: camera.forward,
                }
            }
        }
    }
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` pointing up in the image. The frame is
    /// computed scale-free (see [`unit_direction`]), so any finite eye, target and up work,
    /// however far apart or large.
    pub fn look_at(eye: DVec3, target: DVec3, up: DVec3, projection: Projection) -> Result<Camera> {
        if !eye.is_finite() || !target.is_finite() || !up.is_finite() {
            return Err(Error::config(
                "camera eye, target and up",
                Problem::Must {
                    value: String::new(),
                    requirement: "be finite".into(),
                },
            ));
        }
        let forward = unit_direction(eye, target).ok_or_else(|| {
            Error::config(
                "camera eye",
                Problem::Other {
                    text: format!("{eye} and target {target} coincide"),
                },
            )
        })?;
        let right = unit(up)
            .and_then(|up| unit(forward.cross(up)))
            .ok_or_else(|| {
                Error::config(
                    "camera up",
                    Problem::Other {
                        text: format!("{up} is zero or parallel to the view direction {forward}"),
                    },
                )
            })?;
        match projection {
            Projection::Perspective { fov_deg } => check_fov(fov_deg)?,
            Projection::Orthographic { height } if !(height > 0.0 && height.is_finite()) => {
                return Err(Error::config(
                    "orthographic view height",
                    Problem::Must {
                        value: height.to_string(),
                        requirement: "be positive".into(),
                    },
                ));
            }
            _ => {}
        }
        Ok(Camera {
            eye,
            target,
            projection,
            forward,
            right,
            up: right.cross(forward),
        })
    }

    /// A perspective camera looking at the centre of `bounds` from direction `from`
    /// (eye = centre + distance · from), with vertical field of view `fov_deg` and image aspect
    /// `aspect` (width / height), as close as possible while all eight box corners stay in view
    /// with the [`FRAMING_MARGIN`], centred ([`Camera::frame_points_with_up`]).
    pub fn frame(bounds: &Aabb, from: DVec3, fov_deg: f64, aspect: f64) -> Result<Camera> {
        let corners: Vec<DVec3> = (0..8)
            .map(|k| {
                DVec3::new(
                    if k & 1 == 0 {
                        bounds.min.x
                    } else {
                        bounds.max.x
                    },
                    if k & 2 == 0 {
                        bounds.min.y
                    } else {
                        bounds.max.y
                    },
                    if k & 4 == 0 {
                        bounds.min.z
                    } else {
                        bounds.max.z
                    },
                )
            })
            .collect();
        Camera::frame_points(corners.as_slice(), from, fov_deg, aspect)
    }

    /// Like [`Camera::frame`] but keeps the given points in view (e.g. points sampled on a
    /// surface, which frame it tighter than its box), centred in the image: the camera is
    /// shifted sideways from the centre of their box so that the margins left and right (and
    /// top and bottom) are even on the axis that sets the distance, and the other axis is
    /// centred in the same way.
    /// Up in the image is +y, or +z when looking along y.
    pub fn frame_points<P: FramedPoints + ?Sized>(
        points: &P,
        from: DVec3,
        fov_deg: f64,
        aspect: f64,
    ) -> Result<Camera> {
        let up = if unit(from).is_some_and(|back| back.cross(DVec3::Y).length() > 1e-6) {
            DVec3::Y
        } else {
            DVec3::Z
        };
        Camera::frame_points_with_up(points, from, up, fov_deg, aspect)
    }

    /// [`Camera::frame_points`] with `up` pointing up in the image (it must not be parallel to
    /// `from`).
    pub fn frame_points_with_up<P: FramedPoints + ?Sized>(
        points: &P,
        from: DVec3,
        up: DVec3,
        fov_deg: f64,
        aspect: f64,
    ) -> Result<Camera> {
        Camera::frame_points_looking(points, from, up, fov_deg, aspect, true)
    }

    /// [`Camera::frame_points_with_up`] looking at the centre of the points' box, not
    /// shifted to centre them in the image: the camera that turntables orbit, as every view
    /// of the turn then shares its target.
    pub fn frame_points_at_centre<P: FramedPoints + ?Sized>(
        points: &P,
        from: DVec3,
        up: DVec3,
        fov_deg: f64,
        aspect: f64,
    ) -> Result<Camera> {
        Camera::frame_points_looking(points, from, up, fov_deg, aspect, false)
    }

    /// Automatic framing, centred in the image (`centred`) or looking at the box centre.
    fn frame_points_looking<P: FramedPoints + ?Sized>(
        points: &P,
        from: DVec3,
        up: DVec3,
        fov_deg: f64,
        aspect: f64,
        centred: bool,
    ) -> Result<Camera> {
        let bounds = points.bounds();
        if bounds.is_empty() || !bounds.min.is_finite() || !bounds.max.is_finite() {
            return Err(Error::Invalid(
                "cannot frame an empty or non-finite set of points".into(),
            ));
        }
        check_fov(fov_deg)?;
        if !(aspect > 0.0 && aspect.is_finite()) {
            return Err(Error::config(
                "image aspect",
                Problem::Stated {
                    message: format!("cannot frame with image aspect {aspect}"),
                },
            ));
        }
        let center = bounds.center();
        let back = unit(from).ok_or_else(|| {
            Error::config(
                "framing direction",
                Problem::Must {
                    value: String::new(),
                    requirement: "be non-zero".into(),
                },
            )
        })?;
        let right = unit(up).and_then(|u| unit(u.cross(back))).ok_or_else(|| {
            Error::config(
                "camera up",
                Problem::Other {
                    text: format!(
                        "{up} is zero or parallel to the automatic view direction {}; give \
                         --eye (and --target) to choose the view",
                        -back
                    ),
                },
            )
        })?;
        let true_up = back.cross(right);
        let tan_v = (0.5 * fov_deg.to_radians()).tan() / FRAMING_MARGIN;
        let tan_h = tan_v * aspect;
        // With the eye at centre + s + D·back (s a sideways shift in the image plane), a point
        // c (relative to the centre) is in view when ±(c·right − s·right) ≤ tan_h (D − c·back)
        // and ±(c·up − s·up) ≤ tan_v (D − c·back). Each side needs D ≥ A_side ∓ shift/tan, with
        // A_side the maximum over the points of an affine (so convex) function of p; the shift
        // that makes opposite sides need the same D centres the view with even margins.
        let floor = 1e-6 * bounds.diagonal().max(crate::tolerance::DIVISION_GUARD);
        // Rounding of the affine functions stays far below this margin.
        let reach = bounds.diagonal() + center.abs().max_element();
        let margin = 1e-9 * reach * (1.0 + 1.0 / tan_h.min(tan_v));
        let side = |axis: DVec3, tan: f64| {
            points.max_convex(
                &|p| {
                    let c = p - center;
                    c.dot(back) + c.dot(axis) / tan
                },
                f64::NEG_INFINITY,
                margin,
            )
        };
        let (a_right, a_left) = (side(right, tan_h), side(-right, tan_h));
        let (a_up, a_down) = (side(true_up, tan_v), side(-true_up, tan_v));
        if !centred {
            let distance = a_right.max(a_left).max(a_up).max(a_down).max(floor);
            return Camera::look_at(
                center + back * distance,
                center,
                up,
                Projection::Perspective { fov_deg },
            );
        }
        let distance = (0.5 * (a_right + a_left))
            .max(0.5 * (a_up + a_down))
            .max(floor);
        // The axis that sets the distance is now centred exactly; on the other, points nearer
        // the eye look larger, so the shift is refined until the largest image extents on both
        // sides agree: `extent(axis, s)` is the largest `(c·axis − s)/(D − c·back)`, a
        // quasi-convex function of p (its maximum over a hull is at a hull point), and its
        // slope in `s` is about −1/D on each side.
        let extent = |axis: DVec3, shift: f64| {
            points.max_convex(
                &|p| {
                    let c = p - center;
                    (c.dot(axis) - shift) / (distance - c.dot(back))
                },
                f64::NEG_INFINITY,
                1e-12,
            )
        };
        let imbalance = |axis: DVec3, shift: f64| extent(axis, shift) - extent(-axis, -shift);
        let centred = |axis: DVec3, start: f64| {
            // The imbalance falls as the shift grows: bracket its zero from `start` with steps
            // of the slope estimate, then close in by regula falsi (Illinois variant).
            let (mut a, mut ga) = (start, imbalance(axis, start));
            if ga == 0.0 {
                return a;
            }
            let mut step = 0.5 * distance * ga;
            let (mut b, mut gb) = (a + step, imbalance(axis, a + step));
            for _ in 0..60 {
                if ga.signum() != gb.signum() || gb == 0.0 {
                    break;
                }
                step *= 2.0;
                (a, ga) = (b, gb);
                b = a + step;
                gb = imbalance(axis, b);
            }
            if ga.signum() == gb.signum() {
                return start;
            }
            let mut side = 0;
            for _ in 0..60 {
                let c = (a * gb - b * ga) / (gb - ga);
                let gc = imbalance(axis, c);
                if gc == 0.0 || (b - a).abs() <= 1e-15 * (a.abs() + b.abs() + floor) {
                    return c;
                }
                if gc.signum() == gb.signum() {
                    (b, gb) = (c, gc);
                    if side == 1 {
                        ga *= 0.5;
                    }
                    side = 1;
                } else {
                    (a, ga) = (c, gc);
                    if side == -1 {
                        gb *= 0.5;
                    }
                    side = -1;
                }
            }
            0.5 * (a + b)
        };
        let shift = right * centred(right, 0.5 * (a_right - a_left) * tan_h)
            + true_up * centred(true_up, 0.5 * (a_up - a_down) * tan_v);
        let target = center + shift;
        Camera::look_at(
            target + back * distance,
            target,
            up,
            Projection::Perspective { fov_deg },
        )
    }

    /// The default viewing direction of automatic framing: from the front-right, slightly above.
    pub const DEFAULT_VIEW: DVec3 = DVec3::new(0.55, 0.45, 1.0);

    /// Unit view direction.
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// Unit up direction of the image (orthogonal to [`Camera::forward`]).
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The ray through image-plane point `(x, y)`, both in `[-1, 1]` (x right, y up), for an
    /// image of aspect `aspect` (width / height). For many rays, [`Camera::rays`] computes the
    /// projection's constants once.
    pub fn ray(&self, x: f64, y: f64, aspect: f64) -> Ray64 {
        self.rays(aspect).at(x, y)
    }

    /// The rays of an image of aspect `aspect` (width / height), with the projection's
    /// constants (the tangent of half the field of view) computed once: the renderer asks for
    /// several rays per pixel.
    pub(crate) fn rays(&self, aspect: f64) -> CameraRays<'_> {
        let tan = match self.projection {
            Projection::Perspective { fov_deg } => (0.5 * fov_deg.to_radians()).tan(),
            Projection::Orthographic { .. } => 0.0,
        };
        CameraRays {
            camera: self,
            aspect,
            tan,
        }
    }

    /// World size of one pixel at distance `t` along a ray, for an image `height` pixels high.
    pub fn pixel_footprint(&self, t: f64, height: u32) -> f64 {
        match self.projection {
            Projection::Perspective { fov_deg } => {
                2.0 * t * (0.5 * fov_deg.to_radians()).tan() / f64::from(height)
            }
            Projection::Orthographic { height: h } => h / f64::from(height),
        }
    }

    /// The same camera with an orthographic projection that shows, at the target, what the
    /// perspective view with `fov_deg` shows there.
    pub fn orthographic_of(&self, fov_deg: f64) -> Result<Camera> {
        let height = 2.0 * distance(self.eye, self.target) * (0.5 * fov_deg.to_radians()).tan();
        Camera::look_at(
            self.eye,
            self.target,
            self.up,
            Projection::Orthographic { height },
        )
    }
}

impl Camera {
    /// The camera turned by `angle` radians about the line through the target along `axis`
    /// (right-handed): eye and image frame rotate together, so the target stays in the centre
    /// and its distance, the projection and the tilt against the axis are kept. An angle of 0
    /// gives the camera itself; a zero or non-finite axis or angle is an error.
    pub fn orbit(&self, axis: DVec3, angle: f64) -> Result<Camera> {
        let axis = unit(axis).filter(|a| a.is_finite()).ok_or_else(|| {
            Error::config(
                "orbit axis",
                Problem::Must {
                    value: axis.to_string(),
                    requirement: "be non-zero".into(),
                },
            )
        })?;
        if !angle.is_finite() {
            return Err(Error::config(
                "orbit angle",
                Problem::Must {
                    value: angle.to_string(),
                    requirement: "be finite".into(),
                },
            ));
        }
        if angle == 0.0 {
            return Ok(*self);
        }
        let turn = glam::DQuat::from_axis_angle(axis, angle);
        Camera::look_at(
            self.target + turn * (self.eye - self.target),
            self.target,
            turn * self.up,
            self.projection,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    /// Framing refuses a bad aspect, view direction or up as typed configuration errors,
    /// worded as before.
    #[test]
    fn framing_errors_are_config_errors() {
        let points = [DVec3::ZERO, DVec3::ONE];
        let err = Camera::frame_points(points.as_slice(), Camera::DEFAULT_VIEW, 40.0, 0.0)
            .expect_err("aspect");
        assert_config_error(
            &err,
            "image aspect",
            |p| matches!(p, Problem::Stated { .. }),
            "cannot frame with image aspect 0",
        );
        let err =
            Camera::frame_points(points.as_slice(), DVec3::ZERO, 40.0, 1.0).expect_err("direction");
        assert_config_error(
            &err,
            "framing direction",
            |p| matches!(p, Problem::Must { .. }),
            "framing direction must be non-zero",
        );
        let err = Camera::frame_points_with_up(points.as_slice(), DVec3::Y, DVec3::Y, 40.0, 1.0)
            .expect_err("up");
        assert_config_error(
            &err,
            "camera up",
            |p| matches!(p, Problem::Other { .. }),
            format!(
                "camera up {} is zero or parallel to the automatic view direction {}; give \
                 --eye (and --target) to choose the view",
                DVec3::Y,
                -DVec3::Y
            ),
        );
    }

    #[test]
    fn an_orbit_keeps_distance_and_target_and_closes_after_a_turn() {
        let cam = Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(0.5, 0.0, -1.0),
            DVec3::Y,
            Projection::Perspective { fov_deg: 40.0 },
        )
        .expect("camera");
        assert_eq!(cam.orbit(DVec3::Y, 0.0).expect("orbit"), cam);
        let quarter = cam
            .orbit(DVec3::Y, std::f64::consts::FRAC_PI_2)
            .expect("orbit");
        assert_eq!(quarter.target, cam.target);
        let (d0, d1) = (cam.eye - cam.target, quarter.eye - quarter.target);
        assert!((d0.length() - d1.length()).abs() < 1e-12);
        // About the vertical: the height is kept and the horizontal offset turns by 90°.
        assert!((d0.y - d1.y).abs() < 1e-12);
        assert!((d0.x * d1.x + d0.z * d1.z).abs() < 1e-12);
        // Right-handed: +z turns towards +x about +y.
        assert!((d1.x - d0.z).abs() < 1e-12 && (d1.z + d0.x).abs() < 1e-12);
        assert!((quarter.up().dot(quarter.forward())).abs() < 1e-12);
        let round = (0..8).try_fold(cam, |c, _| {
            c.orbit(DVec3::new(1.0, 1.0, 0.0), std::f64::consts::FRAC_PI_4)
        });
        let round = round.expect("orbit");
        assert!(round.eye.distance(cam.eye) < 1e-12 && round.up().distance(cam.up()) < 1e-12);
        assert!(cam.orbit(DVec3::ZERO, 1.0).is_err());
        assert!(cam.orbit(DVec3::Y, f64::NAN).is_err());
    }

    #[test]
    fn centre_ray_looks_at_target() {
        let cam = Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::ZERO,
            DVec3::Y,
            Projection::Perspective { fov_deg: 40.0 },
        )
        .expect("valid camera");
        let ray = cam.ray(0.0, 0.0, 1.5);
        let to_target = (-cam.eye).normalize();
        assert!((ray.dir - to_target).length() < 1e-15, "{}", ray.dir);
    }

    #[test]
    fn corner_ray_has_the_field_of_view() {
        let fov = 50.0_f64;
        let cam = Camera::look_at(
            DVec3::Z * 4.0,
            DVec3::ZERO,
            DVec3::Y,
            Projection::Perspective { fov_deg: fov },
        )
        .expect("valid camera");
        let top = cam.ray(0.0, 1.0, 1.0);
        let angle = top.dir.angle_between(cam.forward());
        assert!((angle - 0.5 * fov.to_radians()).abs() < 1e-12, "{angle}");
        assert!(top.dir.y > 0.0, "y = +1 is up");
        let right = cam.ray(1.0, 0.0, 1.0);
        assert!(right.dir.x > 0.0, "x = +1 is right when looking down −z");
    }

    #[test]
    fn framing_keeps_every_box_corner_in_view() {
        let b = Aabb {
            min: DVec3::new(-1.0, -0.5, -2.0),
            max: DVec3::new(1.5, 0.5, 1.0),
        };
        let (fov, aspect) = (30.0_f64, 1.5);
        let cam = Camera::frame(&b, Camera::DEFAULT_VIEW, fov, aspect).expect("framing");
        let tan_v = (0.5 * fov.to_radians()).tan();
        let mut widest = 0.0_f64;
        for k in 0..8 {
            let corner = DVec3::new(
                if k & 1 == 0 { b.min.x } else { b.max.x },
                if k & 2 == 0 { b.min.y } else { b.max.y },
                if k & 4 == 0 { b.min.z } else { b.max.z },
            );
            let rel = corner - cam.eye;
            let depth = rel.dot(cam.forward());
            let x = rel.dot(cam.right) / (depth * tan_v * aspect);
            let y = rel.dot(cam.up) / (depth * tan_v);
            assert!(
                x.abs() <= 1.0 && y.abs() <= 1.0,
                "corner {corner} at ({x}, {y})"
            );
            widest = widest.max(x.abs()).max(y.abs());
        }
        assert!(
            (widest - 1.0 / FRAMING_MARGIN).abs() < 1e-12,
            "framing is tight: widest corner at {widest}"
        );
    }

    /// Automatic framing centres the points: the largest image extents left and right (and
    /// up and down) agree, and on the axis that sets the distance they are exactly the
    /// margin's, for point sets far off their box's centre in the image (an L, a cone).
    #[test]
    fn framing_is_centred_with_even_margins() {
        let l_shape: Vec<DVec3> = (0..40)
            .map(|k| {
                let t = f64::from(k) / 39.0;
                if k % 2 == 0 {
                    DVec3::new(3.0 * t, 0.0, 0.2 * t)
                } else {
                    DVec3::new(0.0, 2.0 * t, -1.5 * t)
                }
            })
            .collect();
        let cone: Vec<DVec3> = (0..60)
            .map(|k| {
                let a = f64::from(k) * 0.7;
                let r = f64::from(k % 6) / 5.0;
                DVec3::new(r * a.cos(), 2.0 * (1.0 - r), r * a.sin())
            })
            .collect();
        for (name, points) in [("L", &l_shape), ("cone", &cone)] {
            for (fov, aspect) in [(30.0_f64, 1.5), (40.0, 0.6), (25.0, 1.0)] {
                let cam =
                    Camera::frame_points(points.as_slice(), Camera::DEFAULT_VIEW, fov, aspect)
                        .expect("framing");
                let tan_v = (0.5 * fov.to_radians()).tan();
                let (mut x, mut y) = ([f64::NEG_INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for &p in points {
                    let rel = p - cam.eye;
                    let depth = rel.dot(cam.forward());
                    let (px, py) = (
                        rel.dot(cam.right) / (depth * tan_v * aspect),
                        rel.dot(cam.up) / (depth * tan_v),
                    );
                    x = [x[0].max(px), x[1].max(-px)];
                    y = [y[0].max(py), y[1].max(-py)];
                }
                let case = format!("{name}, fov {fov}, aspect {aspect}: x {x:?}, y {y:?}");
                assert!((x[0] - x[1]).abs() < 1e-12, "left/right uneven: {case}");
                assert!((y[0] - y[1]).abs() < 1e-12, "top/bottom uneven: {case}");
                let widest = x[0].max(y[0]);
                assert!(
                    (widest - 1.0 / FRAMING_MARGIN).abs() < 1e-12,
                    "margin: {case}"
                );
            }
        }
    }

    /// The frame does not depend on the scale: far, huge and tiny cameras give the same view
    /// direction as ordinary ones, and only truly coincident points are refused.
    #[test]
    fn look_at_is_scale_free() {
        let p = Projection::Perspective { fov_deg: 40.0 };
        let reference = Camera::look_at(DVec3::X, DVec3::ZERO, DVec3::Y, p).expect("camera");
        for scale in [1e300, 1e-300, 1e-320, f64::MAX / 2.0] {
            let cam = Camera::look_at(DVec3::X * scale, DVec3::ZERO, DVec3::Y * scale, p)
                .unwrap_or_else(|e| panic!("scale {scale}: {e}"));
            assert!(
                (cam.forward() - reference.forward()).length() < 1e-15,
                "{scale}"
            );
            assert!((cam.up() - reference.up()).length() < 1e-15, "{scale}");
        }
        let opposite = Camera::look_at(DVec3::X * 1e300, -DVec3::X * 1e300, DVec3::Y, p)
            .expect("difference beyond f64::MAX");
        assert_eq!(opposite.forward(), -DVec3::X);
        let ortho = reference
            .orthographic_of(40.0)
            .expect("orthographic at unit distance");
        let far = Camera::look_at(DVec3::X * 1e300, DVec3::ZERO, DVec3::Y, p)
            .and_then(|c| c.orthographic_of(40.0))
            .expect("orthographic far away");
        let height = |c: Camera| match c.projection {
            Projection::Orthographic { height } => height,
            Projection::Perspective { .. } => f64::NAN,
        };
        assert!((height(far) / height(ortho) - 1e300).abs() < 1e286);
    }

    #[test]
    fn framing_takes_the_given_up() {
        let b = Aabb {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        };
        let corners = [b.min, b.max];
        let cam = Camera::frame_points_with_up(
            corners.as_slice(),
            Camera::DEFAULT_VIEW,
            DVec3::X,
            35.0,
            1.0,
        )
        .expect("framing");
        // The image's up is +x made orthogonal to the view direction.
        let f = cam.forward();
        let expected = (DVec3::X - f * f.dot(DVec3::X)).normalize();
        assert!((cam.up() - expected).length() < 1e-15, "up {}", cam.up());
        let err = Camera::frame_points_with_up(
            corners.as_slice(),
            Camera::DEFAULT_VIEW,
            Camera::DEFAULT_VIEW,
            35.0,
            1.0,
        )
        .expect_err("up along the view");
        assert!(err.to_string().contains("parallel"), "{err}");
        let err =
            Camera::frame_points(corners.as_slice(), DVec3::Z, 1e-300, 1.0).expect_err("tiny fov");
        assert!(err.to_string().contains("1e-300°"), "{err}");
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let p = Projection::Perspective { fov_deg: 40.0 };
        assert!(Camera::look_at(DVec3::ONE, DVec3::ONE, DVec3::Y, p).is_err());
        assert!(Camera::look_at(DVec3::Y, DVec3::ZERO, DVec3::Y, p).is_err());
        let bad = Projection::Perspective { fov_deg: 180.0 };
        assert!(Camera::look_at(DVec3::Z, DVec3::ZERO, DVec3::Y, bad).is_err());
    }
}
