//! The buffers a renderer hands to `score`, checked as the command's reader checks their files
//! (`shadowtruth::import::BufferKind`): the camera's shape, and only the values such a file may
//! hold.

use crate::arrays::float32_image;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shadowtruth::ImportedImage;
use shadowtruth::import::BufferKind;

/// `array` as a `kind` buffer of a `(width, height)` camera, or a `ValueError` naming the
/// argument and the pixel at fault.
pub fn buffer_image(
    kind: BufferKind,
    array: &Bound<'_, PyAny>,
    (width, height): (u32, u32),
) -> PyResult<ImportedImage> {
    let name = match kind {
        BufferKind::Visibility => "visibility",
        BufferKind::Depth => "depth",
    };
    let values = float32_image(array, (width, height), name)?;
    if let Some(message) = kind.first_refused(&values, width) {
        return Err(PyValueError::new_err(format!("{name}: {message}")));
    }
    Ok(ImportedImage { path: name.into(), width, height, values })
}
