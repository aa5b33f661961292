//! Batch tests over structure-of-arrays sphere bounds, written as branch-free loops that the
//! compiler vectorises; on x86-64 they are compiled a second time for AVX2+FMA and picked at run
//! time (stable Rust: `#[target_feature]` + `is_x86_feature_detected!`). Same maths and the same
//! rounding slack as the scalar tests, so they accept exactly what those accept.

use std::ops::Range;

use glam::Vec3;

use super::{Cone, Frustum, Sphere};

/// Input a public batch test cannot run on.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BatchError {
    #[error("invalid volumes = {0}: a batch union tests 1 or 2 volumes")]
    VolumeCount(usize),
    #[error("invalid sphere arrays: x, y, z, r have lengths {0:?}; all four must be equal")]
    Lengths([usize; 4]),
    #[error("invalid range = {start}..{end}: within 0..{len}, start ≤ end")]
    Range {
        start: usize,
        end: usize,
        len: usize,
    },
}

/// Sphere bounds as four parallel arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereSoa {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
    pub r: Vec<f32>,
}

impl SphereSoa {
    pub fn with_capacity(n: usize) -> Self {
        Self {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            z: Vec::with_capacity(n),
            r: Vec::with_capacity(n),
        }
    }

    pub fn push(&mut self, s: Sphere) {
        self.x.push(s.center.x);
        self.y.push(s.center.y);
        self.z.push(s.center.z);
        self.r.push(s.radius);
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    pub fn get(&self, i: usize) -> Sphere {
        Sphere::new(Vec3::new(self.x[i], self.y[i], self.z[i]), self.r[i])
    }

    /// Appends the indices in `range` whose sphere may touch any of `frusta` (1 or 2).
    pub fn frustum_union(
        &self,
        frusta: &[Frustum],
        range: Range<usize>,
        out: &mut Vec<u32>,
    ) -> Result<(), BatchError> {
        self.check(frusta.len(), &range)?;
        self.frustum_union_unchecked(frusta, range, out);
        Ok(())
    }

    /// Appends the indices in `range` whose sphere may touch any of `cones` (1 or 2).
    pub fn cone_union(
        &self,
        cones: &[Cone],
        range: Range<usize>,
        out: &mut Vec<u32>,
    ) -> Result<(), BatchError> {
        self.check(cones.len(), &range)?;
        self.cone_union_unchecked(cones, range, out);
        Ok(())
    }

    /// What the public unions accept: 1 or 2 volumes, four arrays of one length, a range
    /// within them.
    fn check(&self, volumes: usize, range: &Range<usize>) -> Result<(), BatchError> {
        if !(1..=2).contains(&volumes) {
            return Err(BatchError::VolumeCount(volumes));
        }
        let lengths = [self.x.len(), self.y.len(), self.z.len(), self.r.len()];
        if lengths.iter().any(|&l| l != lengths[0]) {
            return Err(BatchError::Lengths(lengths));
        }
        if range.start > range.end || range.end > lengths[0] {
            return Err(BatchError::Range {
                start: range.start,
                end: range.end,
                len: lengths[0],
            });
        }
        Ok(())
    }

    /// [`Self::frustum_union`] for the strategies' own calls, whose volumes and ranges come
    /// from the hierarchy and are valid by construction.
    pub(crate) fn frustum_union_unchecked(
        &self,
        frusta: &[Frustum],
        range: Range<usize>,
        out: &mut Vec<u32>,
    ) {
        match frusta {
            [a] => self.run(range, out, |s, m| {
                frustum_mask(&[FrustumParams::new(a)], s, m)
            }),
            [a, b] => self.run(range, out, |s, m| {
                frustum_mask(&[FrustumParams::new(a), FrustumParams::new(b)], s, m)
            }),
            _ => unreachable!("callers pass one or two frusta"),
        }
    }

    /// [`Self::cone_union`] for the strategies' own calls (see `frustum_union_unchecked`).
    pub(crate) fn cone_union_unchecked(
        &self,
        cones: &[Cone],
        range: Range<usize>,
        out: &mut Vec<u32>,
    ) {
        match cones {
            [a] => self.run(range, out, |s, m| cone_mask(&[ConeParams::new(a)], s, m)),
            [a, b] => self.run(range, out, |s, m| {
                cone_mask(&[ConeParams::new(a), ConeParams::new(b)], s, m)
            }),
            _ => unreachable!("callers pass one or two cones"),
        }
    }

    /// Fills visibility masks block by block and appends the passing indices.
    fn run(&self, range: Range<usize>, out: &mut Vec<u32>, mask: impl Fn(Slices<'_>, &mut [bool])) {
        const BLOCK: usize = 256;
        let mut flags = [false; BLOCK];
        let mut start = range.start;
        while start < range.end {
            let end = (start + BLOCK).min(range.end);
            let n = end - start;
            let slices = Slices {
                x: &self.x[start..end],
                y: &self.y[start..end],
                z: &self.z[start..end],
                r: &self.r[start..end],
            };
            mask(slices, &mut flags[..n]);
            // Branch-free compaction: write every index, advance only past the passing ones.
            let mut k = out.len();
            out.resize(k + n, 0);
            for (i, &pass) in flags[..n].iter().enumerate() {
                out[k] = (start + i) as u32;
                k += pass as usize;
            }
            out.truncate(k);
            start = end;
        }
    }
}

/// One block of the four arrays, all the same length.
#[derive(Clone, Copy)]
pub(crate) struct Slices<'a> {
    x: &'a [f32],
    y: &'a [f32],
    z: &'a [f32],
    r: &'a [f32],
}

const SLACK: f32 = 32.0 * f32::EPSILON;

#[derive(Clone, Copy)]
struct FrustumParams {
    o: [f32; 3],
    n: [[f32; 3]; 6],
    w: [f32; 6],
    far: f32,
}

impl FrustumParams {
    fn new(f: &Frustum) -> Self {
        FrustumParams {
            o: f.origin.to_array(),
            n: f.planes.map(|p| p.truncate().to_array()),
            w: f.planes.map(|p| p.w),
            far: f.planes[5].w,
        }
    }
}

#[derive(Clone, Copy)]
struct ConeParams {
    o: [f32; 3],
    axis: [f32; 3],
    tan: f32,
    sin: f32,
    sec: f32,
}

impl ConeParams {
    fn new(c: &Cone) -> Self {
        ConeParams {
            o: c.origin.to_array(),
            axis: c.axis.to_array(),
            tan: c.tan,
            sin: c.sin,
            sec: c.sec,
        }
    }
}

#[inline(always)]
fn frustum_kernel<const N: usize>(ps: &[FrustumParams; N], s: Slices<'_>, mask: &mut [bool]) {
    let n = mask.len();
    let (x, y, z, r) = (&s.x[..n], &s.y[..n], &s.z[..n], &s.r[..n]);
    for i in 0..n {
        let mut any = false;
        for p in ps {
            let (dx, dy, dz) = (x[i] - p.o[0], y[i] - p.o[1], z[i] - p.o[2]);
            let m = dx.abs() + dy.abs() + dz.abs();
            let reach = -(r[i] + SLACK * (m + p.far));
            let mut all = true;
            for k in 0..6 {
                all &= p.n[k][0] * dx + p.n[k][1] * dy + p.n[k][2] * dz + p.w[k] >= reach;
            }
            any |= all;
        }
        mask[i] = any;
    }
}

#[inline(always)]
fn cone_kernel<const N: usize>(ps: &[ConeParams; N], s: Slices<'_>, mask: &mut [bool]) {
    let n = mask.len();
    let (x, y, z, r) = (&s.x[..n], &s.y[..n], &s.z[..n], &s.r[..n]);
    for i in 0..n {
        let mut any = false;
        for p in ps {
            let (cx, cy, cz) = (x[i] - p.o[0], y[i] - p.o[1], z[i] - p.o[2]);
            let m = cx.abs() + cy.abs() + cz.abs();
            let rr = r[i] + SLACK * (m + r[i]);
            let a = cx * p.axis[0] + cy * p.axis[1] + cz * p.axis[2];
            let cc = cx * cx + cy * cy + cz * cz;
            let (px, py, pz) = (cx - p.axis[0] * a, cy - p.axis[1] * a, cz - p.axis[2] * a);
            let reach = a * p.tan + rr * p.sec;
            let behind = a <= -rr * p.sin;
            let apex_hit = cc <= rr * rr;
            let lateral_hit = px * px + py * py + pz * pz <= reach * reach;
            any |= if behind { apex_hit } else { lateral_hit };
        }
        mask[i] = any;
    }
}

macro_rules! dispatch {
    ($name:ident, $kernel:ident, $params:ty) => {
        fn $name<const N: usize>(ps: &[$params; N], s: Slices<'_>, mask: &mut [bool]) {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                fn wide<const N: usize>(ps: &[$params; N], s: Slices<'_>, mask: &mut [bool]) {
                    $kernel(ps, s, mask)
                }
                if has_avx2() {
                    // SAFETY: the CPU supports AVX2 and FMA (checked at run time).
                    return unsafe { wide(ps, s, mask) };
                }
            }
            $kernel(ps, s, mask)
        }
    };
}

dispatch!(frustum_mask, frustum_kernel, FrustumParams);
dispatch!(cone_mask, cone_kernel, ConeParams);

#[cfg(target_arch = "x86_64")]
fn has_avx2() -> bool {
    use std::sync::OnceLock;
    static HAS: OnceLock<bool> = OnceLock::new();
    *HAS.get_or_init(|| is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"))
}

/// Which compiled variant of the batch kernels this CPU runs.
pub fn batch_kernel() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        return "avx2+fma";
    }
    "baseline"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::{look_at_head, FovTangents};

    #[test]
    fn batch_paths_accept_exactly_what_scalar_tests_accept() {
        let frustum = Frustum::from_eye(
            look_at_head(Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 1.0, -9.0)),
            FovTangents::from_angles_deg(44.0, 36.0, 42.0, 48.0),
            0.1,
            80.0,
        );
        let cone = Cone::new(Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.2, -0.1, -1.0), 0.7);
        let mut soa = SphereSoa::default();
        let mut seed = 12345u32;
        let mut rand = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..5000 {
            soa.push(Sphere::new(
                Vec3::new(
                    rand() * 200.0 - 100.0,
                    rand() * 60.0 - 30.0,
                    rand() * 200.0 - 150.0,
                ),
                rand() * 5.0,
            ));
        }
        let mut batch = Vec::new();
        soa.frustum_union(&[frustum], 0..soa.len(), &mut batch)
            .unwrap();
        let scalar: Vec<u32> = (0..soa.len() as u32)
            .filter(|&i| frustum.intersects_sphere(&soa.get(i as usize)))
            .collect();
        assert_eq!(batch, scalar);
        let mut batch = Vec::new();
        soa.cone_union(&[cone], 10..soa.len(), &mut batch).unwrap();
        let scalar: Vec<u32> = (10..soa.len() as u32)
            .filter(|&i| cone.intersects_sphere(&soa.get(i as usize)))
            .collect();
        assert_eq!(batch, scalar);
    }

    /// Mismatched input is an error naming it, not a panic. Mutation: dropping `check` panics
    /// (slice out of range) or silently tests nothing.
    #[test]
    fn bad_input_is_an_error() {
        let mut soa = SphereSoa::default();
        for i in 0..4 {
            soa.push(Sphere::new(Vec3::splat(i as f32), 1.0));
        }
        let frustum = Frustum::from_eye(
            glam::Mat4::IDENTITY,
            crate::view::FovTangents::symmetric_deg(90.0, 90.0),
            0.1,
            100.0,
        );
        let mut out = Vec::new();
        assert_eq!(
            soa.frustum_union(&[frustum; 3], 0..4, &mut out),
            Err(BatchError::VolumeCount(3))
        );
        assert_eq!(
            soa.frustum_union(&[], 0..4, &mut out),
            Err(BatchError::VolumeCount(0))
        );
        assert_eq!(
            soa.frustum_union(&[frustum], 2..9, &mut out),
            Err(BatchError::Range {
                start: 2,
                end: 9,
                len: 4
            })
        );
        soa.r.pop();
        assert_eq!(
            soa.cone_union(&[], 0..3, &mut out),
            Err(BatchError::VolumeCount(0))
        );
        let err = soa.frustum_union(&[frustum], 0..3, &mut out).unwrap_err();
        assert_eq!(err, BatchError::Lengths([4, 4, 4, 3]));
        assert!(err.to_string().contains("[4, 4, 4, 3]"));
        assert!(out.is_empty());
    }
}
