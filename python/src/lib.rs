//! `pointshade._native`: the Rust side of the Python module. Each function here converts
//! Python values and numpy arrays to the library's types, calls the same library function the
//! CLI calls, and converts the result back; the Python package (`python/pointshade/`) adds the
//! `Scene` builder and the keyword interface on top. Nothing here shades or loads by itself.
//!
//! Errors: every `pointshade::error::InputError` becomes a Python exception carrying the CLI's
//! one-line message (`FileNotFoundError` for a missing file, else `pointshade.InputError`, a
//! `ValueError`); arrays of the wrong dtype, shape or layout are a `TypeError` or `ValueError`
//! raised before anything is copied. The GIL is released while loading, rendering and shading.

mod arrays;
mod explore;
mod images;
mod interrupt;
mod material_keys;
mod options;
mod preview;
mod toml_values;
mod workers;

use std::path::{Path, PathBuf};
use std::time::Duration;

use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArrayDyn};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use pointshade::error::InputError as LibError;
use pointshade::film::compare::{compare_checked, Side};
use pointshade::film::Image;
use pointshade::input_files::Confinement;
use pointshade::material::{BrdfModel, Material};
use pointshade::normal_map;
use pointshade::normal_map::formats::min_max_8bit;
use pointshade::normal_map::image::NormalImage;
use pointshade::normal_map::scene_file::{NormalMapScene, Preset};
use pointshade::render::options::Spelling;
use pointshade::render::request::RenderRequest;
use pointshade::render::Rendered;
use pointshade::scene::file::{material_from_toml, MaterialDefaults};
use pointshade::scene::{LoadOptions, Scene, SceneSource};
use pointshade::shading::shader::cook_torrance_terms;
use pointshade::shading::shader::rows::{brdf_rows, FloatRows, RowDomain, RowPrecision};
use pointshade::validation::export::{export_files, ExportOptions};

use arrays::{directions, image_of, ReadFloats};
use interrupt::run_interruptible;
use workers::detached;

pyo3::create_exception!(
    pointshade,
    InputError,
    PyValueError,
    "A problem with something given to pointshade (a file's contents, a parameter): the message is the CLI's one line, `SOURCE: problem`."
);

/// The Python exception of a library error: `FileNotFoundError` when the file is missing, else
/// `pointshade.InputError`; the message is what the CLI prints after `error: `.
pub(crate) fn py_err(e: LibError) -> PyErr {
    let missing = e.problem == "file not found" || e.problem.contains("No such file or directory");
    match missing {
        true => PyFileNotFoundError::new_err(e.to_string()),
        false => InputError::new_err(e.to_string()),
    }
}

/// A `ValueError` about the keyword `name`.
pub(crate) fn value_error(name: &str, problem: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{name}: {problem}"))
}

/// An image's pixels as a float32 (H, W, 3) array, taking over the pixel buffer: an
/// (H, W, 3) float32 array is exactly `Vec<Vec3>`'s memory, and copying 12 bytes a pixel took a
/// noticeable share of a normal image's call (docs/python.md, "Benchmarks").
fn rgb_array<'py>(py: Python<'py>, image: Image) -> Bound<'py, PyArrayDyn<f32>> {
    let shape = (image.height as usize, image.width as usize, 3);
    let flat = vec3_floats(image.pixels);
    Array3::from_shape_vec(shape, flat)
        .expect("one pixel per width × height")
        .into_dyn()
        .into_pyarray(py)
}

/// The floats of `pixels`, without copying them.
fn vec3_floats(pixels: Vec<glam::Vec3>) -> Vec<f32> {
    // glam's Vec3 is `#[repr(C)] { x, y, z: f32 }`: three floats, 4-byte aligned, no padding.
    const _: () = assert!(std::mem::size_of::<glam::Vec3>() == 12 && std::mem::align_of::<glam::Vec3>() == 4);
    let mut pixels = std::mem::ManuallyDrop::new(pixels);
    let (ptr, len, capacity) = (pixels.as_mut_ptr(), pixels.len(), pixels.capacity());
    // SAFETY: the allocation holds `capacity` Vec3s = 3·capacity f32s of the same alignment, the
    // first 3·len of them initialised, and `pixels` no longer owns it.
    unsafe { Vec::from_raw_parts(ptr.cast::<f32>(), 3 * len, 3 * capacity) }
}

/// The confinement of a call's `confine=` folder (every file the call reads must lie in it).
fn confinement(dir: Option<PathBuf>) -> PyResult<Confinement> {
    Confinement::to_optional(dir.as_deref()).map_err(|e| {
        let shown = dir.as_deref().unwrap_or(Path::new("")).display().to_string();
        value_error("confine", format!("{shown}: {e}"))
    })
}

/// The confinement and the request of a call that renders (`function`: its name in errors),
/// from the arguments `render` and `Preview` share.
pub(crate) fn render_request(
    function: &str,
    path: PathBuf,
    text: Option<String>,
    dir: Option<PathBuf>,
    meshes: Option<Bound<'_, PyDict>>,
    confine: Option<PathBuf>,
    options: Option<Bound<'_, PyDict>>,
) -> PyResult<(Confinement, RenderRequest)> {
    let confinement = confinement(confine)?;
    let request = RenderRequest {
        source: scene_source(path, text, dir, meshes.as_ref())?,
        options: options::render_options(function, options.as_ref())?,
    };
    Ok((confinement, request))
}

/// The scene a call names: a file at `path`, or a scene file's `text` (named `path` in
/// messages) whose relative paths start at `dir` and whose meshes `meshes` may give as arrays.
fn scene_source(
    path: PathBuf,
    text: Option<String>,
    dir: Option<PathBuf>,
    meshes: Option<&Bound<'_, PyDict>>,
) -> PyResult<SceneSource> {
    Ok(match text {
        Some(text) => SceneSource::Text {
            name: path,
            text,
            dir: dir.unwrap_or_else(|| PathBuf::from(".")),
            meshes: meshes.map(arrays::mesh_table).transpose()?.unwrap_or_default(),
        },
        None => SceneSource::File(path),
    })
}

/// Renders a scene; `options` holds `pointshade.render`'s keywords (`RENDER_OPTIONS`). Returns
/// a dict: `color`, one entry per AOV, and `stats`.
#[pyfunction]
#[pyo3(signature = (path, *, text=None, dir=None, meshes=None, confine=None, options=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    path: PathBuf,
    text: Option<String>,
    dir: Option<PathBuf>,
    meshes: Option<Bound<'py, PyDict>>,
    confine: Option<PathBuf>,
    options: Option<Bound<'py, PyDict>>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (confinement, request) = render_request("render", path, text, dir, meshes, confine, options)?;
    let progress = progress.map(Bound::unbind);
    let outcome = run_interruptible(py, progress, |stop, latest| -> Result<_, LibError> {
        let prepared = confinement.run(|| request.prepare(Spelling::Keyword))?;
        let rendered = prepared.render(latest, Some(stop))?;
        Ok((prepared, rendered))
    })?;
    let (prepared, rendered) = outcome.map_err(py_err)?;
    rendered_dict(py, rendered, &prepared.scene, prepared.load_time)
}

/// What `render` returns (and a preview's `render`): `color`, one entry per AOV, and `stats`.
pub(crate) fn rendered_dict<'py>(
    py: Python<'py>,
    rendered: Rendered,
    scene: &Scene,
    load_time: Duration,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let (s, region, spp, threshold) = (
        rendered.stats.clone(),
        rendered.region,
        rendered.spp,
        rendered.adaptive_threshold,
    );
    out.set_item("color", rgb_array(py, rendered.image))?;
    for (aov, image) in rendered.aovs {
        out.set_item(aov.name(), rgb_array(py, image))?;
    }
    let stats = PyDict::new(py);
    stats.set_item("load_seconds", load_time.as_secs_f64())?;
    stats.set_item("bvh_seconds", s.bvh_time.as_secs_f64())?;
    stats.set_item("render_seconds", s.wall_time.as_secs_f64())?;
    stats.set_item("surface_seconds", s.surface_time.as_secs_f64())?;
    stats.set_item("shading_seconds", s.shading_time.as_secs_f64())?;
    stats.set_item("primary_rays", s.primary_rays)?;
    stats.set_item("shadow_rays", s.shadow_rays)?;
    stats.set_item("shadow_rays_reused", s.shadow_rays_reused)?;
    stats.set_item("spp", spp)?;
    let pixels = (region.width() as u64 * region.height() as u64).max(1);
    stats.set_item("mean_spp", s.primary_rays as f64 / pixels as f64)?;
    stats.set_item("adaptive_threshold", threshold)?;
    let r = region;
    stats.set_item("region", (r.x0, r.y0, r.x1, r.y1))?;
    stats.set_item("frame", (scene.film.width, scene.film.height))?;
    stats.set_item("exposure", scene.film.exposure)?;
    stats.set_item("triangles", scene.mesh.triangle_count())?;
    stats.set_item("warnings", PyList::new(py, &scene.warnings)?)?;
    out.set_item("stats", stats)?;
    Ok(out)
}

/// L_o of a normal image, the tp preset's 8-bit image when asked for, and the warnings.
type Shaded<'py> = (
    Bound<'py, PyArrayDyn<f32>>,
    Option<Bound<'py, PyArrayDyn<u8>>>,
    Vec<String>,
);

/// Shades a normal image as `pointshade normalmap` does (`pointshade::normal_map::shade`).
/// `text` is a normal-map scene file (its `[normal_map]` image is read unless `normals` gives
/// the samples). Returns L_o as float32 (H, W, 3), the tp preset's 8-bit image when `eight_bit`
/// is set, and the warnings.
#[pyfunction]
#[pyo3(signature = (text, *, normals=None, dir=None, threads=None, eight_bit=false, confine=None))]
fn shade_normal_image<'py>(
    py: Python<'py>,
    text: String,
    normals: Option<Bound<'py, PyAny>>,
    dir: Option<PathBuf>,
    threads: Option<Bound<'py, PyAny>>,
    eight_bit: bool,
    confine: Option<PathBuf>,
) -> PyResult<Shaded<'py>> {
    let confinement = confinement(confine)?;
    let source = Path::new("shade_normal_image");
    let dir = dir.unwrap_or_else(|| PathBuf::from("."));
    let workers = workers::workers(threads.as_ref())?;
    let held = normals
        .as_ref()
        .map(|a| arrays::normal_array(a, &workers))
        .transpose()?;
    let mut samples = held.as_ref().map(|h| (h.width, h.height, h.samples(), h.has_alpha));
    // Milliseconds of work: without the GIL, but not worth a thread that watches for Ctrl-C.
    let outcome = py.detach(|| {
        workers.install(|| -> Result<_, LibError> {
            let (scene, image) = confinement.run(|| -> Result<_, LibError> {
                let scene = NormalMapScene::from_text(source, text.clone(), &dir, None)?;
                let image = match samples.take() {
                    Some((w, h, samples, alpha)) => {
                        NormalImage::from_samples(Path::new("normals"), w, h, samples, alpha)?
                    }
                    None => NormalImage::load(&scene.image)?,
                };
                Ok((scene, image))
            })?;
            let mut shaded = normal_map::shade(&scene, &image, "numpy array of L_o")?;
            let tp_bytes = (eight_bit && scene.preset == Preset::Tp).then(|| {
                let (bytes, range) = min_max_8bit(&shaded.radiance);
                if let Some(warning) = range.warning() {
                    shaded.warnings.push(format!("{}: {warning}", image.source.display()));
                }
                bytes
            });
            Ok((shaded, tp_bytes, scene.preset))
        })
    });
    let (shaded, bytes, preset) = outcome.map_err(py_err)?;
    if eight_bit && preset != Preset::Tp {
        return Err(value_error(
            "return_8bit",
            "the 8-bit image is the tp preset's (min-max normalised); use preset=\"tp\"",
        ));
    }
    let image = shaded.radiance;
    let eight = bytes.map(|b| {
        Array3::from_shape_vec((image.height as usize, image.width as usize, 3), b)
            .expect("three bytes a pixel")
            .into_dyn()
            .into_pyarray(py)
    });
    Ok((rgb_array(py, image), eight, shaded.warnings))
}

/// A material from a `[material.NAME]` section's text, with the scene files' defaults or the
/// tp preset's.
pub(crate) fn material_of(text: &str, defaults: &str) -> PyResult<Material> {
    let defaults = match defaults {
        "scene" => MaterialDefaults::SCENE,
        "tp" => Preset::Tp.material_defaults(),
        other => {
            return Err(value_error(
                "defaults",
                format!("expected 'scene' or 'tp', got '{other}'"),
            ))
        }
    };
    material_from_toml("material", text, &defaults).map_err(|e| InputError::new_err(format!("material: {e}")))
}

/// f_r of `material` (a material section's TOML text) for each row of the (N, 3) arrays, in
/// float32 or float64 (`precision`): `pointshade::shading::shader::brdf_value`, the shader's own,
/// on the arrays in place (`rows::brdf_rows`), without the GIL.
#[pyfunction]
#[pyo3(signature = (material, n, wi, wo, *, precision="float32", defaults="scene"))]
fn eval_brdf<'py>(
    py: Python<'py>,
    material: &str,
    n: Bound<'py, PyAny>,
    wi: Bound<'py, PyAny>,
    wo: Bound<'py, PyAny>,
    precision: &str,
    defaults: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let material = material_of(material, defaults)?;
    let arrays = [
        ReadFloats::rows3("n", &n)?,
        ReadFloats::rows3("wi", &wi)?,
        ReadFloats::rows3("wo", &wo)?,
    ];
    let rows = [arrays[0].rows(), arrays[1].rows(), arrays[2].rows()];
    let count = rows[0].rows();
    if rows.iter().any(|r| r.rows() != count) {
        // Raises, naming the first problem of the arrays as the checks meet it.
        directions(&n, &wi, &wo)?;
    }
    fn eval<'py, T: RowPrecision + numpy::Element>(
        py: Python<'py>,
        material: &Material,
        rows: [FloatRows; 3],
        check: impl FnOnce() -> PyResult<()>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let domain = RowDomain {
            unit_tolerance: arrays::UNIT_TOLERANCE,
        };
        let count = rows[0].rows();
        let (out, inside) = detached(py, || brdf_rows::<T>(material, rows, domain))?;
        if !inside {
            // Some row was near or past a limit: the exact checks name it, or pass it.
            check()?;
        }
        Ok(Array2::from_shape_vec((count, 3), out)
            .expect("3 a row")
            .into_pyarray(py)
            .into_any())
    }
    let check = || directions(&n, &wi, &wo).map(|_| ());
    match precision {
        "float32" => eval::<f32>(py, &material, rows, check),
        "float64" => eval::<f64>(py, &material, rows, check),
        other => Err(value_error(
            "precision",
            format!("expected 'float32' or 'float64', got '{other}'"),
        )),
    }
}

/// The Cook-Torrance terms D, G and F of `material` for each row, with f_r: the functions its
/// `d`, `g` and `fresnel` keys name, of the dot products the shader forms (two-sided materials
/// turn n towards ω_o first). Rows without a shading frame (ω_i = −ω_o) give 0.
#[pyfunction]
#[pyo3(signature = (material, n, wi, wo, *, defaults="scene"))]
fn eval_terms<'py>(
    py: Python<'py>,
    material: &str,
    n: Bound<'py, PyAny>,
    wi: Bound<'py, PyAny>,
    wo: Bound<'py, PyAny>,
    defaults: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let material = material_of(material, defaults)?;
    if !matches!(material.model, BrdfModel::CookTorrance(_)) {
        return Err(value_error(
            "material",
            format!(
                "D, G and F are Cook-Torrance terms; this material is {}",
                material.model_name()
            ),
        ));
    }
    let (n, wi, wo) = directions(&n, &wi, &wo)?;
    let count = n.rows();
    let (mut d, mut g, mut f, mut fr) = (
        Vec::with_capacity(count),
        Vec::with_capacity(count),
        Vec::with_capacity(3 * count),
        Vec::with_capacity(3 * count),
    );
    for i in 0..count {
        let terms = cook_torrance_terms(&material, n.row::<f64>(i), wi.row::<f64>(i), wo.row::<f64>(i))
            .expect("a Cook-Torrance material");
        d.push(terms.d);
        g.push(terms.g);
        f.extend(terms.f);
        fr.extend(terms.f_r);
    }
    let out = PyDict::new(py);
    out.set_item("D", d.into_pyarray(py))?;
    out.set_item("G", g.into_pyarray(py))?;
    out.set_item(
        "F",
        Array2::from_shape_vec((count, 3), f).expect("3 a row").into_pyarray(py),
    )?;
    out.set_item(
        "f_r",
        Array2::from_shape_vec((count, 3), fr)
            .expect("3 a row")
            .into_pyarray(py),
    )?;
    Ok(out)
}

/// The metrics `pointshade compare` prints, for two float (H, W, 3) arrays, with the per-pixel
/// relative errors as a float32 (H, W) array.
#[pyfunction]
#[pyo3(signature = (ours, reference, *, tol=1e-3, worst=10, count_non_finite=false))]
fn compare<'py>(
    py: Python<'py>,
    ours: Bound<'py, PyAny>,
    reference: Bound<'py, PyAny>,
    tol: f32,
    worst: usize,
    count_non_finite: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(value_error("tol", format!("must be a finite number ≥ 0, got {tol}")));
    }
    let ours = image_of("ours", &ours)?;
    let reference = image_of("ref", &reference)?;
    let c = detached(py, || compare_checked(&ours, &reference, tol, worst, count_non_finite))?.map_err(
        |(side, problem)| match side {
            Side::Ours => value_error("ours", problem),
            Side::Reference => value_error("ref", problem),
        },
    )?;
    let out = PyDict::new(py);
    out.set_item("pixels", c.pixels)?;
    out.set_item("rmse", c.rmse)?;
    out.set_item("rel_mse", c.rel_mse)?;
    out.set_item("mean_relative_error", c.mean_relative_error)?;
    out.set_item("within_tolerance", c.within_tolerance)?;
    out.set_item("tolerance", c.tolerance)?;
    out.set_item("non_finite_ours", c.non_finite_ours)?;
    out.set_item("non_finite_reference", c.non_finite_reference)?;
    let worst = PyList::empty(py);
    for w in &c.worst {
        let d = PyDict::new(py);
        d.set_item("x", w.x)?;
        d.set_item("y", w.y)?;
        d.set_item("relative_error", w.relative_error)?;
        d.set_item("ours", w.ours.to_array())?;
        d.set_item("reference", w.reference.to_array())?;
        worst.append(d)?;
    }
    out.set_item("worst", worst)?;
    out.set_item("summary", c.summary())?;
    let errors =
        Array2::from_shape_vec((ours.height as usize, ours.width as usize), c.relative_errors).expect("one a pixel");
    out.set_item("relative_error", errors.into_pyarray(py))?;
    Ok(out)
}

/// A linear image file (EXR, or PNG decoded to linear) as a float32 (H, W, 3) array.
#[pyfunction]
fn read_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let image = detached(py, || Confinement::NONE.run(|| pointshade::output::read_linear(&path)))?.map_err(py_err)?;
    Ok(rgb_array(py, image))
}

/// Writes a scene (a file at `path`, or a scene file's `text` whose meshes `meshes` may give as
/// arrays) as Mitsuba 3 XML at `output`, as `pointshade export-mitsuba` does, with the meshes
/// Mitsuba cannot read beside it; returns the lines the CLI prints (material notes, differences).
#[pyfunction]
#[pyo3(signature = (path, output, *, text=None, dir=None, meshes=None, spp=None, sampler=None, matching=None, per_light=false))]
#[allow(clippy::too_many_arguments)]
fn export_mitsuba<'py>(
    py: Python<'py>,
    path: PathBuf,
    output: PathBuf,
    text: Option<String>,
    dir: Option<PathBuf>,
    meshes: Option<Bound<'py, PyDict>>,
    spp: Option<u32>,
    sampler: Option<String>,
    matching: Option<String>,
    per_light: bool,
) -> PyResult<Vec<String>> {
    let source = scene_source(path, text, dir, meshes.as_ref())?;
    let options = ExportOptions {
        spp,
        sampler,
        matching,
        per_light,
        plugin_everywhere: false,
    };
    detached(py, || -> Result<Vec<String>, LibError> {
        let scene = Confinement::NONE.run(|| source.load(LoadOptions::default()))?;
        let (files, lines) = export_files(scene, &output, &options, &|key| key.to_string())?;
        pointshade::output::write_all_or_nothing(&files)?;
        Ok(lines)
    })?
    .map_err(py_err)
}

/// Writes a mesh's arrays as the OBJ file that loads exactly as they do
/// (`pointshade::scene::obj::MeshArrays::to_obj`), all or nothing.
#[pyfunction]
#[pyo3(signature = (path, vertices, faces, normals=None, uvs=None))]
fn write_obj(
    py: Python<'_>,
    path: PathBuf,
    vertices: Bound<'_, PyAny>,
    faces: Bound<'_, PyAny>,
    normals: Option<Bound<'_, PyAny>>,
    uvs: Option<Bound<'_, PyAny>>,
) -> PyResult<()> {
    let none = py.None().into_bound(py);
    let arrays = arrays::mesh_arrays(
        &format!("mesh {}", path.display()),
        &vertices,
        &faces,
        normals.as_ref().unwrap_or(&none),
        uvs.as_ref().unwrap_or(&none),
    )?;
    detached(py, || {
        pointshade::output::write_all_or_nothing(&[(path, arrays.to_obj().into_bytes())])
    })?
    .map_err(py_err)
}

/// A TOML document's text from a dict of str, bool, int, float, lists and dicts; errors name
/// `context` (the call the values came from) and the key.
#[pyfunction]
#[pyo3(signature = (value, context=""))]
fn to_toml(value: Bound<'_, PyDict>, context: &str) -> PyResult<String> {
    let table = toml_values::table_of(&value, context)?;
    toml::to_string(&table).map_err(|e| value_error("to_toml", e))
}

/// A TOML document as a dict; errors name `name` and the line.
#[pyfunction]
fn parse_toml<'py>(py: Python<'py>, text: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let table = pointshade::scene::file::parse_toml_table(Path::new(name), text.to_string()).map_err(py_err)?;
    toml_values::py_of(py, &toml::Value::Table(table))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // `multiprocessing` forks on Linux, possibly while another thread is in a call.
    pointshade::process_fork::prepare_for_forks();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(shade_normal_image, m)?)?;
    m.add_class::<preview::Preview>()?;
    m.add_class::<explore::ExploreServer>()?;
    m.add_function(wrap_pyfunction!(eval_brdf, m)?)?;
    m.add_function(wrap_pyfunction!(eval_terms, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(read_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::to_srgb8, m)?)?;
    m.add_function(wrap_pyfunction!(images::png_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_normal_image, m)?)?;
    m.add_function(wrap_pyfunction!(export_mitsuba, m)?)?;
    m.add_function(wrap_pyfunction!(to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(write_obj, m)?)?;
    m.add_function(wrap_pyfunction!(parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(options::render_option_table, m)?)?;
    m.add_function(wrap_pyfunction!(material_keys::material_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(material_keys::term_names, m)?)?;
    Ok(())
}
