//! The images buffer the kernels read (`kernels::abi::IMAGE_HEADER_WORDS`):
//! one header per image, then each image's texels followed by its mip
//! levels (`super::mips`).

use super::mips::mip_levels;
use super::Image;
use crate::error::{Error, Result};
use kernels::abi::IMAGE_HEADER_WORDS;

/// Largest images buffer, in `u32` words: offsets are `u32`, and wgpu
/// binds at most 2^31 bytes on common adapters.
pub const MAX_IMAGE_WORDS: usize = 1 << 29;

/// The images buffer of `images` and the image count; `colour[i]` says
/// whether image `i` is read as colour (its mip levels are averaged in
/// linear light; missing entries count as colour).
///
/// # Errors
/// [`Error::InvalidImage`] for an empty image or a wrong texel count,
/// [`Error::SceneTooLarge`] past [`MAX_IMAGE_WORDS`].
pub(super) fn pack_images(images: &[Image], colour: &[bool]) -> Result<(Vec<u32>, u32)> {
    let header = images.len() * IMAGE_HEADER_WORDS as usize;
    // Level 0 and the mip chain (at most 1/3 more for square images, 1/2
    // more for a long strip; the check below counts what is stored).
    let texels: usize = images.iter().map(|i| i.texels.len()).sum();
    if header + texels > MAX_IMAGE_WORDS {
        return Err(Error::SceneTooLarge {
            what: "texels",
            count: header + texels,
            limit: MAX_IMAGE_WORDS,
        });
    }
    let mut out = vec![0u32; header];
    for (i, image) in images.iter().enumerate() {
        let expected = image.width as usize * image.height as usize;
        if image.width == 0 || image.height == 0 || image.texels.len() != expected {
            return Err(Error::InvalidImage {
                name: image.name.clone(),
                width: image.width,
                height: image.height,
                texels: image.texels.len(),
            });
        }
        let levels = mip_levels(image, colour.get(i).copied().unwrap_or(true));
        let h = i * IMAGE_HEADER_WORDS as usize;
        out[h] = out.len() as u32;
        out[h + 1] = image.width;
        out[h + 2] = image.height;
        out[h + 3] = 1 + levels.len() as u32;
        out.extend(image.texels.iter().map(|t| u32::from_le_bytes(*t)));
        for (_, _, texels) in &levels {
            out.extend(texels.iter().map(|t| u32::from_le_bytes(*t)));
        }
        if out.len() > MAX_IMAGE_WORDS {
            return Err(Error::SceneTooLarge {
                what: "texels with their mip levels",
                count: out.len(),
                limit: MAX_IMAGE_WORDS,
            });
        }
    }
    if out.is_empty() {
        out.push(0);
    }
    Ok((out, images.len() as u32))
}
