//! Reference masks as grey PNGs.

use shadowtruth::atomic_file::{encode_gray_png, write_atomic};
use std::path::Path;

/// A mask in the `MaskCode` grey levels.
pub fn write_mask_png(path: &Path, width: u32, height: u32, codes: &[u8]) -> std::io::Result<()> {
    write_atomic(path, &encode_gray_png(width, height, codes)?)
}
