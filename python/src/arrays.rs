//! numpy arrays in: dtype, shape, layout and finiteness checked before use, each failure a
//! `TypeError` (wrong dtype or not an array) or `ValueError` (shape, layout, NaN) naming the
//! argument. Arrays are read in place: nothing is copied to convert a layout, and only a normal
//! image's three-channel or float arrays are converted (to the RGBA samples the shading reads).

use std::borrow::Cow;

use numpy::{
    Element, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pointshade::film::Image;
use pointshade::lanes::Scalar;
use pointshade::normal_map::image::{Samples, UnitSample};
use pointshade::render::Workers;
use pointshade::scene::file::MeshTable;
use pointshade::scene::obj::MeshArrays;
use pointshade::shading::shader::rows::FloatRows;

use crate::value_error;

/// `value` as a numpy array, C-contiguous, of `ndim` dimensions whose trailing ones are
/// `trailing` (`None`: any length).
fn array<'a, 'py>(
    name: &str,
    value: &'a Bound<'py, PyAny>,
    ndim: usize,
    trailing: &[Option<usize>],
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    let a = value
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a numpy array, got {}", type_name(value))))?;
    let shape = a.shape();
    // Images are (H, W, C), lists of rows (N, C).
    let letters: &[&str] = if ndim == 3 { &["H", "W", "C"] } else { &["N", "C"] };
    let wanted = || {
        let free = std::iter::repeat_n(None, ndim - trailing.len());
        let dims: Vec<String> = free
            .chain(trailing.iter().copied())
            .enumerate()
            .map(|(i, t)| t.map_or(letters.get(i).unwrap_or(&"N").to_string(), |n| n.to_string()))
            .collect();
        format!("({})", dims.join(", "))
    };
    let tail_ok = shape.len() == ndim
        && shape[ndim - trailing.len()..]
            .iter()
            .zip(trailing)
            .all(|(&s, t)| t.is_none_or(|t| s == t));
    if !tail_ok {
        return Err(value_error(name, format!("expected shape {}, got {shape:?}", wanted())));
    }
    if !a.is_c_contiguous() {
        return Err(value_error(
            name,
            "must be C-contiguous (pass np.ascontiguousarray(...): pointshade does not copy arrays silently)",
        ));
    }
    Ok(a)
}

fn type_name(value: &Bound<'_, PyAny>) -> String {
    value.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

/// The dtype's name, for messages.
fn dtype_name(a: &Bound<'_, PyUntypedArray>) -> String {
    a.dtype().to_string()
}

/// `read` of the elements of a C-contiguous array of element type `T`, if that is its dtype.
fn with_elements<T: Element, R>(a: &Bound<'_, PyUntypedArray>, read: impl FnOnce(&[T]) -> R) -> Option<R> {
    let typed = a.cast::<PyArrayDyn<T>>().ok()?;
    let ro = typed.readonly();
    ro.as_slice().ok().map(read)
}

/// The elements of a C-contiguous array of element type `T`, if that is its dtype.
fn elements<T: Element + Copy>(a: &Bound<'_, PyUntypedArray>) -> Option<Vec<T>> {
    with_elements(a, <[T]>::to_vec)
}

/// Float elements (float32 or float64) as f64, each checked finite.
fn finite_floats(name: &str, a: &Bound<'_, PyUntypedArray>) -> PyResult<Vec<f64>> {
    let values = match elements::<f64>(a) {
        Some(v) => v,
        None => match elements::<f32>(a) {
            Some(v) => v.into_iter().map(f64::from).collect(),
            None => return Err(not_float(name, a)),
        },
    };
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(value_error(
            name,
            format!("element {i} is {} (every value must be finite)", values[i]),
        ));
    }
    Ok(values)
}

fn not_float(name: &str, a: &Bound<'_, PyUntypedArray>) -> PyErr {
    PyTypeError::new_err(format!(
        "{name}: expected a float32 or float64 array, got dtype {}",
        dtype_name(a)
    ))
}

/// A float32 or float64 numpy array borrowed for reading in place (numpy's borrow flag is
/// held until it drops).
pub enum ReadFloats<'py> {
    F32(PyReadonlyArrayDyn<'py, f32>),
    F64(PyReadonlyArrayDyn<'py, f64>),
}

impl ReadFloats<'_> {
    /// The (N, 3) array `value` of `name`, shape and dtype checked (its values are not).
    pub fn rows3<'py>(name: &str, value: &Bound<'py, PyAny>) -> PyResult<ReadFloats<'py>> {
        let a = array(name, value, 2, &[Some(3)])?;
        if let Ok(typed) = a.cast::<PyArrayDyn<f32>>() {
            return Ok(ReadFloats::F32(typed.readonly()));
        }
        match a.cast::<PyArrayDyn<f64>>() {
            Ok(typed) => Ok(ReadFloats::F64(typed.readonly())),
            Err(_) => Err(not_float(name, a)),
        }
    }

    /// The elements, in place.
    pub fn rows(&self) -> FloatRows<'_> {
        const CHECKED: &str = "C-contiguous: checked by `array`";
        match self {
            ReadFloats::F32(a) => FloatRows::F32(a.as_slice().expect(CHECKED)),
            ReadFloats::F64(a) => FloatRows::F64(a.as_slice().expect(CHECKED)),
        }
    }
}

/// Integer elements of any integer dtype as u32 indices, each checked in range of u32.
fn indices(name: &str, a: &Bound<'_, PyUntypedArray>) -> PyResult<Vec<u32>> {
    let bad = |v: i128| value_error(name, format!("index {v} is negative or too large"));
    macro_rules! try_dtype {
        ($($t:ty),*) => {
            $(if let Some(v) = elements::<$t>(a) {
                return v.into_iter().map(|x| u32::try_from(x).map_err(|_| bad(x as i128))).collect();
            })*
        };
    }
    try_dtype!(i64, i32, u32, u64, i16, u16, u8, i8);
    Err(PyTypeError::new_err(format!(
        "{name}: expected an integer array, got dtype {}",
        dtype_name(a)
    )))
}

/// The meshes of a `{name: (vertices, faces, normals | None, uvs | None)}` dict.
pub fn mesh_table(meshes: &Bound<'_, PyDict>) -> PyResult<MeshTable> {
    let mut table = MeshTable::new();
    for (key, value) in meshes.iter() {
        let name: String = key.extract()?;
        let (vertices, faces, normals, uvs): (Bound<PyAny>, Bound<PyAny>, Bound<PyAny>, Bound<PyAny>) =
            value.extract()?;
        let arrays = mesh_arrays(&format!("mesh '{name}'"), &vertices, &faces, &normals, &uvs)?;
        table.insert(name, arrays);
    }
    Ok(table)
}

/// A mesh's arrays: (N, 3) float `vertices`, (M, 3) integer `faces`, and (N, 3) `normals` and
/// (N, 2) `uvs` or `None`; messages name the part after `what` (`mesh 'x' vertices`).
pub fn mesh_arrays(
    what: &str,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    normals: &Bound<'_, PyAny>,
    uvs: &Bound<'_, PyAny>,
) -> PyResult<MeshArrays> {
    let what = |part: &str| format!("{what} {part}");
    let positions = finite_floats(&what("vertices"), array(&what("vertices"), vertices, 2, &[Some(3)])?)?;
    let faces = indices(&what("faces"), array(&what("faces"), faces, 2, &[Some(3)])?)?;
    if faces.is_empty() {
        return Err(value_error(&what("faces"), "no faces: nothing to render"));
    }
    let optional = |part: &str, value: &Bound<PyAny>, width: usize| -> PyResult<Vec<f64>> {
        match value.is_none() {
            true => Ok(Vec::new()),
            false => finite_floats(&what(part), array(&what(part), value, 2, &[Some(width)])?),
        }
    };
    Ok(MeshArrays {
        normals: optional("normals", normals, 3)?,
        uvs: optional("uvs", uvs, 2)?,
        positions,
        indices: faces,
    })
}

/// A normal image array, held for the call: (H, W, 4) uint8 and uint16 arrays are read where
/// they lie (numpy's borrow flag is held until this drops; every integer level is a valid
/// sample), others are converted to RGBA samples once.
pub struct NormalArray<'py> {
    pub width: u32,
    pub height: u32,
    /// Whether the array has an alpha channel.
    pub has_alpha: bool,
    held: HeldSamples<'py>,
}

enum HeldSamples<'py> {
    Eight(PyReadonlyArrayDyn<'py, u8>),
    Sixteen(PyReadonlyArrayDyn<'py, u16>),
    Converted(Samples<'static>),
}

impl NormalArray<'_> {
    /// The RGBA samples, borrowed from the array or from their conversion.
    pub fn samples(&self) -> Samples<'_> {
        const CHECKED: &str = "C-contiguous: checked by `array`";
        match &self.held {
            HeldSamples::Eight(a) => Samples::Eight(Cow::Borrowed(a.as_slice().expect(CHECKED).as_chunks().0)),
            HeldSamples::Sixteen(a) => Samples::Sixteen(Cow::Borrowed(a.as_slice().expect(CHECKED).as_chunks().0)),
            HeldSamples::Converted(s) => s.borrowed(),
        }
    }
}

/// An (H, W, 3|4) uint8, uint16 or float normal image array `value`, checked and held for
/// reading ([`NormalArray`]); a conversion runs on `workers`.
pub fn normal_array<'py>(value: &Bound<'py, PyAny>, workers: &Workers) -> PyResult<NormalArray<'py>> {
    let a = array("normals", value, 3, &[None])?;
    let shape = a.shape();
    let (h, w, c) = (shape[0], shape[1], shape[2]);
    if c != 3 && c != 4 {
        return Err(value_error(
            "normals",
            format!("expected (H, W, 3) or (H, W, 4), got {shape:?}"),
        ));
    }
    let size = |v: usize| u32::try_from(v).map_err(|_| value_error("normals", format!("{w}×{h} is too large")));
    let (width, height, has_alpha) = (size(w)?, size(h)?, c == 4);
    let held = |held| {
        Ok(NormalArray {
            width,
            height,
            has_alpha,
            held,
        })
    };
    if has_alpha {
        if let Ok(typed) = a.cast::<PyArrayDyn<u8>>() {
            return held(HeldSamples::Eight(typed.readonly()));
        }
        if let Ok(typed) = a.cast::<PyArrayDyn<u16>>() {
            return held(HeldSamples::Sixteen(typed.readonly()));
        }
    }
    /// Each pixel's samples as RGBA (`full` for a missing alpha), converted by `to`, in parallel
    /// on `workers`.
    fn rgba<S: Copy + Sync, T: Copy + Send + Sync>(
        workers: &Workers,
        v: &[S],
        c: usize,
        full: T,
        to: impl Fn(S) -> T + Sync,
    ) -> Vec<[T; 4]> {
        workers.install(|| match c {
            3 => rgba_of::<3, S, T>(v, full, &to),
            _ => rgba_of::<4, S, T>(v, full, &to),
        })
    }
    /// [`rgba`] for `C` channels: a loop of fixed shape per block of pixels, which the
    /// compiler turns into vector shuffles (a copy for four 8-bit channels).
    fn rgba_of<const C: usize, S: Copy + Sync, T: Copy + Send + Sync>(
        v: &[S],
        full: T,
        to: impl Fn(S) -> T + Sync,
    ) -> Vec<[T; 4]> {
        use rayon::prelude::*;
        const BLOCK: usize = 16384;
        let n = v.len() / C;
        let mut out = Vec::with_capacity(n);
        out.spare_capacity_mut()[..n]
            .par_chunks_mut(BLOCK)
            .zip(v.par_chunks(C * BLOCK))
            .for_each(|(out, v)| {
                for (o, p) in out.iter_mut().zip(v.chunks_exact(C)) {
                    o.write([to(p[0]), to(p[1]), to(p[2]), if C == 4 { to(p[3]) } else { full }]);
                }
            });
        // SAFETY: the blocks above cover the first n elements (v holds n whole pixels, C
        // samples each), and each was written once.
        unsafe { out.set_len(n) };
        out
    }
    let unit = UnitSample(1.0);
    let samples = if let Some(s) = with_elements(a, |v| rgba(workers, v, c, u8::MAX, |x| x)) {
        Samples::Eight(s.into())
    } else if let Some(s) = with_elements(a, |v| rgba(workers, v, c, u16::MAX, |x| x)) {
        Samples::Sixteen(s.into())
    } else if let Some(s) = with_elements(a, |v: &[f32]| rgba(workers, v, c, unit, UnitSample)) {
        Samples::Float(s.into())
    } else if let Some(s) = with_elements(a, |v: &[f64]| rgba(workers, v, c, unit, |x| UnitSample(x as f32))) {
        Samples::Float(s.into())
    } else {
        return Err(PyTypeError::new_err(format!(
            "normals: expected a uint8, uint16 or float array (a PNG's samples, or them divided by full scale), got dtype {}",
            dtype_name(a)
        )));
    };
    held(HeldSamples::Converted(samples))
}

/// An (H, W, 3) uint8 array's width, height and bytes (8-bit sRGB, as a PNG stores them), or
/// `None` when `value` is an array of another dtype.
pub fn rgb8_of(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Option<(u32, u32, Vec<u8>)>> {
    let is_u8 = value
        .cast::<PyUntypedArray>()
        .is_ok_and(|a| a.dtype().is_equiv_to(&numpy::dtype::<u8>(value.py())));
    if !is_u8 {
        return Ok(None);
    }
    let a = array(name, value, 3, &[None, None, Some(3)])?;
    let size = |v: usize| u32::try_from(v).map_err(|_| value_error(name, "too large"));
    let (height, width) = (size(a.shape()[0])?, size(a.shape()[1])?);
    Ok(elements::<u8>(a).map(|bytes| (width, height, bytes)))
}

/// An (H, W, 3) float array as an image (NaN and infinity kept: the comparison counts them).
pub fn image_of(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Image> {
    let a = array(name, value, 3, &[None, None, Some(3)])?;
    let shape = a.shape();
    let values: Vec<f32> = match elements::<f32>(a) {
        Some(v) => v,
        None => match elements::<f64>(a) {
            Some(v) => v.into_iter().map(|x| x as f32).collect(),
            None => return Err(not_float(name, a)),
        },
    };
    let size = |v: usize| u32::try_from(v).map_err(|_| value_error(name, "too large"));
    Ok(Image {
        width: size(shape[1])?,
        height: size(shape[0])?,
        pixels: values.chunks_exact(3).map(glam::Vec3::from_slice).collect(),
    })
}

/// An (N, 3) array of directions, as f64 (converted to the evaluation's precision per row).
pub struct DirectionArray(Vec<f64>);

impl DirectionArray {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.0.len() / 3
    }

    /// Each row's index and length.
    fn lengths(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..self.rows()).map(|i| (i, glam::DVec3::from_array(self.row::<f64>(i)).length()))
    }

    /// Row `i` in precision `R`.
    pub fn row<R: Scalar>(&self, i: usize) -> [R; 3] {
        [
            R::lit(self.0[3 * i]),
            R::lit(self.0[3 * i + 1]),
            R::lit(self.0[3 * i + 2]),
        ]
    }
}

/// How far from 1 the length of a `wi` or `wo` row may be: well above the rounding of a float32
/// normalisation (about 1e-7), well below any length given by mistake.
pub const UNIT_TOLERANCE: f64 = 1e-4;

/// `n`, `wi` and `wo` as (N, 3) direction arrays of one length, finite; `wi` and `wo` unit
/// (to [`UNIT_TOLERANCE`]), `n` of any length but zero.
pub fn directions(
    n: &Bound<'_, PyAny>,
    wi: &Bound<'_, PyAny>,
    wo: &Bound<'_, PyAny>,
) -> PyResult<(DirectionArray, DirectionArray, DirectionArray)> {
    let read = |name: &str, v: &Bound<'_, PyAny>| -> PyResult<DirectionArray> {
        Ok(DirectionArray(finite_floats(name, array(name, v, 2, &[Some(3)])?)?))
    };
    let (n, wi, wo) = (read("n", n)?, read("wi", wi)?, read("wo", wo)?);
    for (name, d) in [("wi", &wi), ("wo", &wo)] {
        if let Some((row, length)) = d.lengths().find(|(_, l)| (l - 1.0).abs() > UNIT_TOLERANCE) {
            return Err(value_error(
                name,
                format!("row {row} has length {length} (directions must be unit vectors, to {UNIT_TOLERANCE:e}): normalise the rows"),
            ));
        }
    }
    if let Some((row, _)) = n.lengths().find(|&(_, l)| l == 0.0) {
        return Err(value_error(
            "n",
            format!("row {row} is zero: a normal needs a direction (any length)"),
        ));
    }
    if n.rows() != wi.rows() || n.rows() != wo.rows() {
        return Err(value_error(
            "wi",
            format!(
                "n, wi and wo need one row each per direction: {}, {}, {} rows",
                n.rows(),
                wi.rows(),
                wo.rows()
            ),
        ));
    }
    Ok((n, wi, wo))
}
