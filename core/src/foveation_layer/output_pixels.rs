//! An output image's texels as the 8-bit sRGB pixels of an [`RgbaImage`]: an sRGB output as it
//! is; a linear one (8-bit UNORM, or half floats) encoded, so a read-back frame shows and
//! compares the same whatever format the plan renders into.

use crate::plan::Format;
use crate::scene::textures::encode_srgb;

/// `texels` (tightly packed, `format`) as 8-bit sRGB RGBA, alpha kept linear.
pub(super) fn to_srgb8(format: Format, texels: &[u8]) -> Vec<u8> {
    match format {
        Format::Rgba8Unorm => texels
            .chunks_exact(4)
            .flat_map(|t| {
                let c = |v: u8| encode_srgb(v as f32 / 255.0);
                [c(t[0]), c(t[1]), c(t[2]), t[3]]
            })
            .collect(),
        Format::Rgba16F => texels
            .chunks_exact(8)
            .flat_map(|t| {
                let h = |i: usize| half_to_f32(u16::from_le_bytes([t[2 * i], t[2 * i + 1]]));
                let alpha = (h(3).clamp(0.0, 1.0) * 255.0).round() as u8;
                [
                    encode_srgb(h(0)),
                    encode_srgb(h(1)),
                    encode_srgb(h(2)),
                    alpha,
                ]
            })
            .collect(),
        _ => texels.to_vec(),
    }
}

/// An IEEE 754 half float's value.
fn half_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Half floats decode to their values: zero, one, a half, the smallest subnormal, the
    /// largest finite, negatives; and linear values encode as sRGB does.
    #[test]
    fn half_floats_and_linear_texels_become_srgb() {
        assert_eq!(half_to_f32(0x0000), 0.0);
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0x3800), 0.5);
        assert_eq!(half_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(half_to_f32(0x7bff), 65504.0);
        assert_eq!(half_to_f32(0xc000), -2.0);
        assert!(half_to_f32(0x7c00).is_infinite());
        // Linear 0.5 is sRGB 188; 1.0 stays 255; alpha stays linear.
        let half = |v: u16| v.to_le_bytes();
        let texel: Vec<u8> = [half(0x3800), half(0x3c00), half(0), half(0x3800)].concat();
        assert_eq!(to_srgb8(Format::Rgba16F, &texel), vec![188, 255, 0, 128]);
        assert_eq!(
            to_srgb8(Format::Rgba8Unorm, &[128, 255, 0, 77]),
            vec![188, 255, 0, 77]
        );
    }
}
