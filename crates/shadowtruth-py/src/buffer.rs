//! The buffers a renderer hands to `score`, checked as the command's reader checks their files:
//! the camera's shape, and only the values such a file may hold.

use crate::arrays::float32_image;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shadowtruth::ImportedImage;

#[derive(Clone, Copy)]
pub enum Buffer {
    /// 1 lit, 0 shadowed; NaN or negative where the renderer drew background.
    Visibility,
    /// Distance from the camera along each primary ray; 0 or +inf for background.
    Depth,
}

impl Buffer {
    fn name(self) -> &'static str {
        match self {
            Buffer::Visibility => "visibility",
            Buffer::Depth => "depth",
        }
    }

    /// Whether the command's reader refuses `value` in such a file.
    fn refuses(self, value: f32) -> bool {
        match self {
            Buffer::Visibility => value > 1.0,
            Buffer::Depth => value.is_nan() || value < 0.0,
        }
    }

    /// The rule a refused value breaks, in the reader's words.
    fn rule(self) -> &'static str {
        match self {
            Buffer::Visibility => "visibility must be in [0, 1] (NaN or negative for background)",
            Buffer::Depth => "depth must be ≥ 0 (0 or +inf for background)",
        }
    }

    /// `array` as this buffer of a `(width, height)` camera, or a `ValueError` naming the
    /// argument and the pixel at fault.
    pub fn image(self, array: &Bound<'_, PyAny>, (width, height): (u32, u32)) -> PyResult<ImportedImage> {
        let name = self.name();
        let values = float32_image(array, (width, height), name)?;
        if let Some(i) = values.iter().position(|&v| self.refuses(v)) {
            let (x, y) = (i as u32 % width, i as u32 / width);
            let message = format!("{name}: pixel ({x}, {y}) is {}: {}", values[i], self.rule());
            return Err(PyValueError::new_err(message));
        }
        Ok(ImportedImage { path: name.into(), width, height, values })
    }
}
