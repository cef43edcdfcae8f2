//! `shadowtruth reference --kind coverage|area`: a soft reference as a two-channel f32 EXR
//! (`V` visibility, `E` its standard error; row 0 at the top; the samples per pixel in a
//! `samples` header attribute), written atomically.

use shadowtruth::atomic_file::write_atomic;
use shadowtruth::trace::SoftReference;
use std::path::Path;

pub fn write_soft_exr(path: &Path, reference: &SoftReference) -> std::io::Result<()> {
    write_atomic(path, &reference.to_exr()?)
}
