//! Images out of Python: files as the CLI writes them, and 8-bit sRGB arrays and PNG bytes for
//! notebooks. All of it goes through `pointshade::output`, the CLI's encoders, so a render
//! saved from Python is the CLI's file byte for byte.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::IntoPyArray;
use numpy::PyArrayDyn;
use pointshade::film::Image;
use pointshade::input_files::Confinement;
use pointshade::normal_map::image::{NormalImage, Samples};
use pointshade::output::{encode, encode_png8, srgb8_pixels, write_all_or_nothing, Format};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::arrays::{image_of, rgb8_of};
use crate::workers::detached;
use crate::{py_err, value_error};

/// `array` (float (H, W, 3)) as an image to encode: every pixel finite (an output file never
/// holds a NaN), `exposure` a finite number of stops.
fn finite_image(array: &Bound<'_, PyAny>, exposure: f64) -> PyResult<Image> {
    if !exposure.is_finite() {
        return Err(value_error(
            "exposure",
            format!("must be a finite number of stops, got {exposure}"),
        ));
    }
    let image = image_of("array", array)?;
    if let Some((x, y, v)) = detached(array.py(), || image.first_non_finite())? {
        return Err(value_error(
            "array",
            format!(
                "pixel (x {x}, y {y}) is not finite ({}, {}, {}): nothing written",
                v.x, v.y, v.z
            ),
        ));
    }
    Ok(image)
}

/// Writes a float (H, W, 3) image as `pointshade render -o` writes one: `.png` 8-bit sRGB after
/// scaling by 2^`exposure` and clamping to [0, 1], `.exr` linear float32 (exposure not
/// applied); a uint8 (H, W, 3) array (8-bit sRGB already) only to a `.png`, as it is. All or
/// nothing.
#[pyfunction]
#[pyo3(signature = (path, array, *, exposure=0.0))]
pub fn write_image(py: Python<'_>, path: PathBuf, array: Bound<'_, PyAny>, exposure: f64) -> PyResult<()> {
    let format = Format::of_output(&path).map_err(py_err)?;
    let bytes = match rgb8_of("array", &array)? {
        Some(_) if format == Format::Exr => {
            return Err(value_error(
                "array",
                "a uint8 array is 8-bit sRGB, which an EXR (linear float) cannot hold: write a .png, or pass the float render",
            ))
        }
        Some(_) if exposure != 0.0 => {
            return Err(value_error("exposure", "applies to float images only (a uint8 array is written as it is)"))
        }
        Some((width, height, rgb)) => detached(py, || encode_png8(width, height, rgb))?,
        None => {
            let image = finite_image(&array, exposure)?;
            detached(py, || encode(&image, format, exposure as f32))?
        }
    };
    let bytes = bytes.map_err(|e| value_error("array", e))?;
    detached(py, || write_all_or_nothing(&[(path, bytes)]))?.map_err(py_err)
}

/// The 8-bit sRGB pixels a PNG of the image holds, as a uint8 (H, W, 3) array.
#[pyfunction]
#[pyo3(signature = (array, *, exposure=0.0))]
pub fn to_srgb8<'py>(py: Python<'py>, array: Bound<'py, PyAny>, exposure: f64) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let image = finite_image(&array, exposure)?;
    let bytes = detached(py, || srgb8_pixels(&image, exposure as f32))?;
    let shape = (image.height as usize, image.width as usize, 3);
    Ok(Array3::from_shape_vec(shape, bytes)
        .expect("three bytes a pixel")
        .into_dyn()
        .into_pyarray(py))
}

/// The PNG file's bytes of the image (what `write_image` writes to a `.png`), for notebooks.
#[pyfunction]
#[pyo3(signature = (array, *, exposure=0.0))]
pub fn png_bytes<'py>(py: Python<'py>, array: Bound<'py, PyAny>, exposure: f64) -> PyResult<Bound<'py, PyBytes>> {
    let image = finite_image(&array, exposure)?;
    let bytes = detached(py, || encode(&image, Format::Png, exposure as f32))?.map_err(|e| value_error("array", e))?;
    Ok(PyBytes::new(py, &bytes))
}

/// A PNG normal image's samples as the file stores them: uint8 or uint16, (H, W, 3), or
/// (H, W, 4) when it has alpha; what `shade_normal_image` takes as an array. Decoded and checked
/// as `pointshade normalmap` reads it (errors name the file).
#[pyfunction]
pub fn read_normal_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let image = detached(py, || Confinement::NONE.run(|| NormalImage::load(&path)))?.map_err(py_err)?;
    let channels = if image.has_alpha { 4 } else { 3 };
    let shape = (image.height as usize, image.width as usize, channels);
    fn array<'py, T: numpy::Element + Copy>(
        py: Python<'py>,
        shape: (usize, usize, usize),
        pixels: &[[T; 4]],
    ) -> Bound<'py, PyAny> {
        let values = pixels.iter().flat_map(|p| p[..shape.2].iter().copied()).collect();
        let a = Array3::from_shape_vec(shape, values).expect("one pixel per width × height");
        a.into_dyn().into_pyarray(py).into_any()
    }
    Ok(match &image.samples {
        Samples::Eight(p) => array(py, shape, p),
        Samples::Sixteen(p) => array(py, shape, p),
        Samples::Float(_) => unreachable!("a PNG file holds integer samples"),
    })
}
