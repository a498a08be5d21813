//! Affine transforms of Mitsuba 3's `<transform>` element, in f64 (host-side only; the kernel never
//! sees f64): `matrix`, `translate`, `rotate`, `scale` and `lookat`, each applied after the ones
//! before it (M = op · M), as Mitsuba composes them.

/// An affine map x ↦ L x + t, stored as the top three rows of a 4x4 matrix (row-major).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Affine {
    pub(crate) m: [[f64; 4]; 3],
}

/// A 3-vector in f64.
pub(crate) type V3 = [f64; 3];

impl Affine {
    pub(crate) const IDENTITY: Affine =
        Affine { m: [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]] };

    /// From a linear part given by its columns and a translation.
    pub(crate) fn from_columns(x: V3, y: V3, z: V3, t: V3) -> Affine {
        let mut m = [[0.0; 4]; 3];
        for (r, row) in m.iter_mut().enumerate() {
            *row = [x[r], y[r], z[r], t[r]];
        }
        Affine { m }
    }

    pub(crate) fn translate(t: V3) -> Affine {
        Affine::from_columns([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], t)
    }

    pub(crate) fn scale(s: V3) -> Affine {
        Affine::from_columns([s[0], 0.0, 0.0], [0.0, s[1], 0.0], [0.0, 0.0, s[2]], [0.0; 3])
    }

    /// Rotation by `angle_deg` degrees about `axis` (right-handed), as Mitsuba's
    /// `Transform4f::rotate`. `None` for a zero axis.
    pub(crate) fn rotate(axis: V3, angle_deg: f64) -> Option<Affine> {
        let len = dot(axis, axis).sqrt();
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return None;
        }
        let [x, y, z] = axis.map(|a| a / len);
        let (s, c) = angle_deg.to_radians().sin_cos();
        let k = 1.0 - c;
        Some(Affine {
            m: [
                [x * x * k + c, x * y * k - z * s, x * z * k + y * s, 0.0],
                [x * y * k + z * s, y * y * k + c, y * z * k - x * s, 0.0],
                [x * z * k - y * s, y * z * k + x * s, z * z * k + c, 0.0],
            ],
        })
    }

    /// Mitsuba's `lookat`: columns (left, up', dir, origin) with dir = normalize(target - origin),
    /// left = normalize(up × dir), up' = dir × left. `None` if degenerate.
    pub(crate) fn look_at(origin: V3, target: V3, up: V3) -> Option<Affine> {
        let dir = normalize(sub(target, origin))?;
        let left = normalize(cross(up, dir))?;
        let new_up = cross(dir, left);
        Some(Affine::from_columns(left, new_up, dir, origin))
    }

    /// `self` applied after `inner`: self · inner.
    pub(crate) fn after(&self, inner: &Affine) -> Affine {
        let (a, b) = (&self.m, &inner.m);
        let mut m = [[0.0; 4]; 3];
        for (r, row) in m.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                let mut s = a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c];
                if c == 3 {
                    s += a[r][3];
                }
                *v = s;
            }
        }
        Affine { m }
    }

    /// The image of point p.
    pub(crate) fn point(&self, p: V3) -> V3 {
        self.m.map(|row| row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3])
    }

    /// Column `c` of the linear part (the image of a unit axis vector).
    pub(crate) fn column(&self, c: usize) -> V3 {
        [self.m[0][c], self.m[1][c], self.m[2][c]]
    }

    /// Determinant of the linear part.
    pub(crate) fn det(&self) -> f64 {
        dot(cross(self.column(0), self.column(1)), self.column(2))
    }

    pub(crate) fn is_finite(&self) -> bool {
        self.m.iter().flatten().all(|v| v.is_finite())
    }
}

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn normalize(a: V3) -> Option<V3> {
    let len = dot(a, a).sqrt();
    (len > 0.0 && len.is_finite()).then(|| a.map(|v| v / len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: V3, b: V3) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    #[test]
    fn composes_in_document_order() {
        // translate then rotate 90 degrees about z: (1,0,0) -> (1,0,0)+(1,0,0) -> (0,2,0)
        let t = Affine::translate([1.0, 0.0, 0.0]);
        let r = Affine::rotate([0.0, 0.0, 1.0], 90.0).unwrap();
        let m = r.after(&t.after(&Affine::IDENTITY));
        assert!(close(m.point([1.0, 0.0, 0.0]), [0.0, 2.0, 0.0]));
        let s = Affine::scale([2.0, 3.0, 4.0]);
        assert!(close(s.after(&m).point([1.0, 0.0, 0.0]), [0.0, 6.0, 0.0]));
        assert!(Affine::rotate([0.0; 3], 1.0).is_none());
        assert!((Affine::scale([2.0, 3.0, -1.0]).det() + 6.0).abs() < 1e-12);
    }

    #[test]
    fn look_at_is_mitsubas() {
        let m = Affine::look_at([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        // Looking down -z: dir = -z, left = up x dir = -x... Mitsuba's x axis is "left".
        assert!(close(m.column(2), [0.0, 0.0, -1.0]));
        assert!(close(m.column(0), [-1.0, 0.0, 0.0]));
        assert!(close(m.column(1), [0.0, 1.0, 0.0]));
        assert!(close(m.point([0.0; 3]), [0.0, 0.0, 5.0]));
        assert!(Affine::look_at([0.0; 3], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]).is_none());
    }
}
