use super::FovTangents;
use glam::{Mat4, Vec4};

/// Reverse-Z perspective projection for Vulkan clip space from four FOV tangents.
///
/// Maps the view-space frustum edges x/−z ∈ [−left, right] to NDC x ∈ [−1, 1] and
/// y/−z ∈ [−down, up] to NDC y ∈ [1, −1] (Vulkan's y points down); depth is 1 at `near` and
/// 0 at `far`. `far = f32::INFINITY` gives the infinite reverse-Z projection.
pub fn reverse_z_projection(fov: FovTangents, near: f32, far: f32) -> Mat4 {
    let FovTangents {
        left,
        right,
        up,
        down,
    } = fov;
    let w = left + right;
    let h = up + down;
    // depth = (a·z + b) / −z with depth(−near) = 1 and depth(−far) = 0.
    let (a, b) = if far.is_infinite() {
        (0.0, near)
    } else {
        (near / (far - near), near * far / (far - near))
    };
    Mat4::from_cols(
        Vec4::new(2.0 / w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -2.0 / h, 0.0, 0.0),
        Vec4::new((right - left) / w, (down - up) / h, a, -1.0),
        Vec4::new(0.0, 0.0, b, 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// f64 oracle: where a view-space point lands in NDC, straight from the definitions.
    fn ndc_oracle(fov: FovTangents, near: f64, far: f64, p: [f64; 3]) -> [f64; 3] {
        let (l, r, u, d) = (
            fov.left as f64,
            fov.right as f64,
            fov.up as f64,
            fov.down as f64,
        );
        let tx = p[0] / -p[2];
        let ty = p[1] / -p[2];
        let x = (tx + l) / (l + r) * 2.0 - 1.0;
        let y = -((ty + d) / (u + d) * 2.0 - 1.0);
        let depth = near * (far + p[2]) / (p[2] * (near - far));
        [x, y, depth]
    }

    fn project(m: Mat4, p: [f64; 3]) -> [f64; 3] {
        let c = m * Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32).extend(1.0);
        [(c.x / c.w) as f64, (c.y / c.w) as f64, (c.z / c.w) as f64]
    }

    #[test]
    fn asymmetric_frustum_edges_map_to_ndc_edges() {
        // Rift CV1-like asymmetric eye.
        let fov = FovTangents::from_angles_deg(42.0, 36.0, 47.0, 41.0);
        let (near, far) = (0.1, 100.0);
        let m = reverse_z_projection(fov, near, far);
        let z = -3.0;
        let corners = [
            (
                [-fov.left as f64 * 3.0, fov.up as f64 * 3.0, z],
                [-1.0, -1.0],
            ),
            (
                [fov.right as f64 * 3.0, -fov.down as f64 * 3.0, z],
                [1.0, 1.0],
            ),
        ];
        for (p, want) in corners {
            let got = project(m, p);
            assert!(
                (got[0] - want[0]).abs() < 1e-5 && (got[1] - want[1]).abs() < 1e-5,
                "{got:?}"
            );
        }
        let near_pt = project(m, [0.0, 0.0, -near as f64]);
        let far_pt = project(m, [0.0, 0.0, -far as f64]);
        assert!((near_pt[2] - 1.0).abs() < 1e-6, "near depth {}", near_pt[2]);
        assert!(far_pt[2].abs() < 1e-6, "far depth {}", far_pt[2]);
    }

    #[test]
    fn matches_f64_oracle_across_depths() {
        let fov = FovTangents::from_angles_deg(54.4, 46.8, 55.7, 55.9);
        let (near, far) = (0.05f32, 500.0f32);
        let m = reverse_z_projection(fov, near, far);
        for &z in &[-0.05, -0.5, -7.0, -99.0, -499.0] {
            for &(x, y) in &[(0.0, 0.0), (0.3, -0.2), (-1.1, 0.9)] {
                let p = [x * -z, y * -z, z];
                let got = project(m, p);
                let want = ndc_oracle(fov, near as f64, far as f64, p);
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-5,
                        "z {z}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn infinite_far_keeps_depth_positive_and_decreasing() {
        let m = reverse_z_projection(FovTangents::symmetric_deg(90.0, 90.0), 0.1, f32::INFINITY);
        let d1 = project(m, [0.0, 0.0, -10.0])[2];
        let d2 = project(m, [0.0, 0.0, -1e6])[2];
        assert!(d1 > d2 && d2 > 0.0);
    }
}
