//! `pointshade bake`: a mesh scene → BVH → one camera ray per pixel centre → its camera-space
//! normals as an RGBA PNG in the NPM3D assignment's format (see [`pointshade::normal_map::bake`]).

use std::path::PathBuf;
use std::time::Instant;

use crate::options::workers;
use pointshade::accel::Bvh;
use pointshade::error::InputError;
use pointshade::normal_map::bake::bake_normals;
use pointshade::normal_map::formats::encode_normal_png;
use pointshade::output::{write_all_or_nothing, Format};
use pointshade::scene;

/// Arguments of `pointshade bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    /// Scene file (.toml) or mesh (.obj).
    scene: PathBuf,
    /// Output normal image (.png).
    #[arg(short, long)]
    output: PathBuf,
    /// Image width in pixels.
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    height: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// No summary.
    #[arg(long, short)]
    quiet: bool,
}

/// Runs `pointshade bake`.
pub fn run(args: BakeArgs) -> Result<(), InputError> {
    let start = Instant::now();
    if Format::of_output(&args.output)? != Format::Png {
        return Err(InputError::new(
            &args.output,
            "a baked normal image is written as PNG (the assignment's format)",
        ));
    }
    let pool = workers(args.threads)?;
    let mut scene = pool.install(|| scene::load(&args.scene))?;
    let f = &mut scene.film;
    f.width = args.width.unwrap_or(f.width);
    f.height = args.height.unwrap_or(f.height);
    f.validate().map_err(|e| InputError::new(&args.scene, e))?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let baked = pool.install(|| {
        let bvh = Bvh::for_scene(&scene);
        bake_normals(&scene, &bvh)
    });
    let baked = baked.map_err(|e| InputError::new(&args.scene, e))?;
    let bytes =
        encode_normal_png(baked.width, baked.height, &baked.normals).map_err(|e| InputError::new(&args.output, e))?;
    write_all_or_nothing(&[(args.output.clone(), bytes)])?;
    if !args.quiet {
        eprintln!(
            "baked {}x{} camera-space normals ({} pixels hit, {} rays) in {:.2} s → {}",
            baked.width,
            baked.height,
            baked.hits(),
            baked.normals.len(),
            start.elapsed().as_secs_f64(),
            args.output.display()
        );
    }
    Ok(())
}
