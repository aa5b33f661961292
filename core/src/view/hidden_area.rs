//! A runtime's hidden-area mesh (OpenXR `XR_KHR_visibility_mask`, hidden triangle mesh): the
//! triangles of each view its lens never shows, in the view's tangent space. The HMD stencil
//! mask drops them, in place of the ellipse fitted to a profile's published fraction.

use glam::{DVec2, Vec2};

use super::{polygon, FovTangents};

/// The most triangles a view's hidden area may have (the mask's uniform block holds them).
pub const MAX_HIDDEN_TRIANGLES: usize = 128;

/// One view's hidden triangles: tangent-space points (x right, y up, on the plane z = −1).
#[derive(Clone, Debug, PartialEq)]
pub struct HiddenArea {
    /// The triangles, at most [`MAX_HIDDEN_TRIANGLES`].
    pub triangles: Vec<[Vec2; 3]>,
}

impl HiddenArea {
    /// From an indexed mesh as a runtime gives it; refuses indices out of range, a count that
    /// is no multiple of three, points that are not finite and more than
    /// [`MAX_HIDDEN_TRIANGLES`] triangles.
    pub fn from_indexed(vertices: &[Vec2], indices: &[u32]) -> Result<Self, String> {
        if !indices.len().is_multiple_of(3) {
            return Err(format!(
                "hidden-area mesh: {} indices, not whole triangles",
                indices.len()
            ));
        }
        if indices.len() / 3 > MAX_HIDDEN_TRIANGLES {
            return Err(format!(
                "hidden-area mesh: {} triangles, at most {MAX_HIDDEN_TRIANGLES}",
                indices.len() / 3
            ));
        }
        let point = |i: u32| {
            vertices
                .get(i as usize)
                .copied()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "hidden-area mesh: index {i} of {} vertices, or a point that is not finite",
                        vertices.len()
                    )
                })
        };
        let triangles = indices
            .chunks_exact(3)
            .map(|t| Ok([point(t[0])?, point(t[1])?, point(t[2])?]))
            .collect::<Result<_, String>>()?;
        Ok(HiddenArea { triangles })
    }

    /// The triangles in the NDC of a view with field `fov` (Vulkan's: y down).
    pub fn ndc(&self, fov: FovTangents) -> Vec<[Vec2; 3]> {
        self.triangles
            .iter()
            .map(|t| t.map(|p| fov.ndc(p)))
            .collect()
    }

    /// The fraction of a view with field `fov` the triangles hide: their area inside the view
    /// (each clipped to it), over the view's (pixels are evenly spread in NDC). Runtimes give
    /// non-overlapping triangles; overlaps would count twice.
    pub fn hidden_fraction(&self, fov: FovTangents) -> f64 {
        let area: f64 = self
            .ndc(fov)
            .iter()
            .map(|t| {
                let t = t.map(|p| p.as_dvec2()).to_vec();
                polygon::area(&polygon::clip_to_rect(t, DVec2::NEG_ONE, DVec2::ONE))
            })
            .sum();
        area / 4.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fov() -> FovTangents {
        FovTangents::symmetric_deg(90.0, 90.0)
    }

    #[test]
    fn a_hidden_corner_hides_its_area() {
        // The view's lower-left quarter as two triangles (tangents ±1 at 90°).
        let v = [
            Vec2::new(-1.0, -1.0),
            Vec2::new(0.0, -1.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(-1.0, 0.0),
        ];
        let mesh = HiddenArea::from_indexed(&v, &[0, 1, 2, 0, 2, 3]).unwrap();
        assert!((mesh.hidden_fraction(fov()) - 0.25).abs() < 1e-6);
    }

    #[test]
    fn what_lies_outside_the_view_hides_nothing() {
        // A triangle half outside the left edge: only its inside half counts.
        let v = [
            Vec2::new(-2.0, -1.0),
            Vec2::new(0.0, -1.0),
            Vec2::new(-2.0, 1.0),
        ];
        let mesh = HiddenArea::from_indexed(&v, &[0, 1, 2]).unwrap();
        // Inside x ≥ −1: the triangle (−1,−1),(0,−1),(−1,0) in tangents = 0.5 of the view's 4
        // NDC units² → 1/8.
        assert!((mesh.hidden_fraction(fov()) - 0.125).abs() < 1e-6);
    }

    #[test]
    fn bad_meshes_are_refused_with_what_is_wrong() {
        let v = [Vec2::ZERO, Vec2::X, Vec2::Y];
        assert!(HiddenArea::from_indexed(&v, &[0, 1])
            .unwrap_err()
            .contains("whole triangles"));
        assert!(HiddenArea::from_indexed(&v, &[0, 1, 3])
            .unwrap_err()
            .contains("index 3"));
        let nan = [Vec2::ZERO, Vec2::X, Vec2::NAN];
        assert!(HiddenArea::from_indexed(&nan, &[0, 1, 2])
            .unwrap_err()
            .contains("not finite"));
        let many = vec![0u32; 3 * (MAX_HIDDEN_TRIANGLES + 1)];
        assert!(HiddenArea::from_indexed(&v, &many)
            .unwrap_err()
            .contains("at most"));
    }
}
