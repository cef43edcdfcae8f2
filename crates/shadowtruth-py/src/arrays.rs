//! numpy arrays in and out: images are `(height, width)` arrays, row 0 at the top, as the
//! command's PNG and EXR files hold them.

use numpy::{PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `values` (row by row, `width` per row) as a `(height, width)` array.
pub fn image_array<T: numpy::Element>(
    py: Python<'_>,
    width: u32,
    values: Vec<T>,
) -> PyResult<Bound<'_, PyArray2<T>>> {
    let shape = (values.len() / width.max(1) as usize, width as usize);
    let array = numpy::ndarray::Array2::from_shape_vec(shape, values)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(PyArray2::from_owned_array(py, array))
}

/// The values of `array`, row by row, once it is checked to be a float32 numpy array of shape
/// `(height, width)`; `what` names the argument in the error.
pub fn float32_image(
    array: &Bound<'_, PyAny>,
    (width, height): (u32, u32),
    what: &str,
) -> PyResult<Vec<f32>> {
    let expected = format!("a float32 numpy array of shape ({height}, {width})");
    let untyped = array.cast::<PyUntypedArray>().map_err(|_| {
        let type_name = array.get_type().name().map(|n| n.to_string()).unwrap_or_default();
        PyValueError::new_err(format!("{what}: expected {expected}, got {type_name}"))
    })?;
    let dtype = untyped.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<f32>(array.py())) {
        return Err(PyValueError::new_err(format!(
            "{what}: expected {expected}, got dtype {} (convert with .astype(numpy.float32))",
            dtype.str()?
        )));
    }
    if untyped.shape() != [height as usize, width as usize] {
        return Err(PyValueError::new_err(format!(
            "{what}: expected {expected} (the camera's image), got shape {}",
            python_shape(untyped.shape())
        )));
    }
    let typed = array.cast::<PyArray2<f32>>()?;
    // Any memory layout: iterated in logical (row-major) order.
    Ok(typed.readonly().as_array().iter().copied().collect())
}

/// A shape as Python prints it: `(480, 640)`, `(3,)`.
fn python_shape(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}
