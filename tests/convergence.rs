//! `pointshade convergence`: the CSV lists every point with a falling error, and the plots exist.

use std::path::Path;
use std::process::Command;

#[test]
fn convergence_writes_csv_and_plots_with_falling_error() {
    let d = std::env::temp_dir().join(format!("pointshade-convergence-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let lambert = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lambert.toml")).unwrap();
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let small = lambert
        .replace("width = 512", "width = 96")
        .replace("height = 384", "height = 72")
        .replace("../meshes", meshes.to_str().unwrap());
    let scene = d.join("small.toml");
    std::fs::write(&scene, small).unwrap();
    let bin = env!("CARGO_BIN_EXE_pointshade");
    let reference = d.join("ref.exr");
    let r = Command::new(bin)
        .args([
            "render",
            scene.to_str().unwrap(),
            "-o",
            reference.to_str().unwrap(),
            "--sampler",
            "grid",
            "--spp",
            "256",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = d.join("out");
    let r = Command::new(bin)
        .args([
            "convergence",
            scene.to_str().unwrap(),
            "--reference",
            reference.to_str().unwrap(),
        ])
        .args([
            "--spp",
            "1,4,16",
            "--sampler",
            "sobol,adaptive,grid",
            "--repeats",
            "2",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let csv = std::fs::read_to_string(out.join("convergence.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .filter(|l| l.starts_with("pointshade,"))
        .map(|l| l.split(',').collect())
        .collect();
    // sobol and adaptive at 1, 4, 16; grid at the squares 1, 4, 16.
    assert_eq!(rows.len(), 9, "{csv}");
    for sampler in ["sobol", "grid"] {
        let rmse: Vec<f64> = rows
            .iter()
            .filter(|r| r[1] == sampler)
            .map(|r| r[6].parse().unwrap())
            .collect();
        assert!(
            rmse.windows(2).all(|w| w[1] < w[0]),
            "{sampler}: error must fall with samples: {rmse:?}"
        );
    }
    for row in &rows {
        let times: Vec<f64> = row[5].split(' ').map(|t| t.parse().unwrap()).collect();
        assert_eq!(times.len(), 2, "two repeats timed");
    }
    for f in ["convergence.svg", "convergence.png", "reference.png"] {
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 1000, "{f}");
    }
    let svg = std::fs::read_to_string(out.join("convergence.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("polyline"),
        "the SVG has the error lines"
    );
    std::fs::remove_dir_all(d).unwrap();
}
