//! Where a present puts each image it shows: the sources side by side, scaled by one factor
//! to fit the window and centred, on whole pixels (a 1:1 fit copies texels unchanged). Pure
//! arithmetic, tested without a window.

use ash::vk;

/// A region of an image to show: layer `layer`, `width` × `height` texels from column `x`, in
/// `TRANSFER_SRC_OPTIMAL` (where a renderer leaves its outputs).
#[derive(Clone, Copy, Debug)]
pub struct BlitSource {
    /// The image.
    pub image: vk::Image,
    /// Its layer shown.
    pub layer: u32,
    /// The first column shown.
    pub x: u32,
    /// Columns shown.
    pub width: u32,
    /// Rows shown, from the top.
    pub height: u32,
}

/// Where each source lands: side by side, scaled by one factor to fit `extent`, centred.
/// Whole pixels; a 1:1 fit copies texels unchanged.
pub(super) fn fit_side_by_side(
    sources: &[BlitSource],
    extent: vk::Extent2D,
) -> Vec<(BlitSource, [vk::Offset3D; 2])> {
    let width: u32 = sources.iter().map(|s| s.width).sum();
    let height = sources.iter().map(|s| s.height).max().unwrap_or(0);
    if width == 0 || height == 0 {
        return Vec::new();
    }
    let scale = (extent.width as f64 / width as f64).min(extent.height as f64 / height as f64);
    let (w, h) = (
        (width as f64 * scale).floor() as i32,
        (height as f64 * scale).floor() as i32,
    );
    let (x0, y0) = (
        (extent.width as i32 - w) / 2,
        (extent.height as i32 - h) / 2,
    );
    let mut x = 0u32;
    sources
        .iter()
        .map(|s| {
            let left = x0 + (x as f64 * scale).round() as i32;
            x += s.width;
            let right = x0 + (x as f64 * scale).round() as i32;
            let top = y0;
            let bottom = y0 + (s.height as f64 * scale).round() as i32;
            (
                *s,
                [
                    vk::Offset3D {
                        x: left,
                        y: top,
                        z: 0,
                    },
                    vk::Offset3D {
                        x: right,
                        y: bottom,
                        z: 1,
                    },
                ],
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(width: u32, height: u32) -> BlitSource {
        BlitSource {
            image: vk::Image::null(),
            layer: 0,
            x: 0,
            width,
            height,
        }
    }

    #[test]
    fn eyes_fit_side_by_side_and_centred() {
        let eyes = [source(64, 64), source(64, 64)];
        let exact = fit_side_by_side(
            &eyes,
            vk::Extent2D {
                width: 128,
                height: 64,
            },
        );
        assert_eq!((exact[0].1[0].x, exact[0].1[1].x), (0, 64));
        assert_eq!((exact[1].1[0].x, exact[1].1[1].x), (64, 128));
        // A taller window: scaled to its width, centred vertically.
        let tall = fit_side_by_side(
            &eyes,
            vk::Extent2D {
                width: 256,
                height: 300,
            },
        );
        assert_eq!((tall[1].1[0].x, tall[1].1[1].x), (128, 256));
        assert_eq!((tall[0].1[0].y, tall[0].1[1].y), (86, 214));
        // A wider one: scaled to its height, centred horizontally.
        let wide = fit_side_by_side(
            &eyes,
            vk::Extent2D {
                width: 400,
                height: 32,
            },
        );
        assert_eq!((wide[0].1[0].x, wide[1].1[1].x), (168, 232));
    }
}
