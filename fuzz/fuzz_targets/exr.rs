//! EXR files as `compare` and `merge` read them: a whole image (read_linear) and a crop
//! (placement from the header, then pixels), then compared with itself and merged alone.
#![no_main]
use libfuzzer_sys::fuzz_target;
use pointshade::output::exr::{check_tiling, merge, read_crop, read_crop_placement};

fuzz_target!(|data: &[u8]| {
    let path = pointshade_fuzz::put("i.exr", data);
    if let Ok(image) = pointshade::output::read_linear(&path) {
        if let Ok(c) = pointshade::film::compare::compare_checked(&image, &image, 1e-3, 3, false) {
            assert!(c.rmse == 0.0, "an image differs from itself: {}", c.rmse);
        }
    }
    if let Ok((region, frame)) = read_crop_placement(&path) {
        let placement = [(path.clone(), region, frame)];
        let tiles = check_tiling(&placement).is_ok();
        if let Ok(crop) = read_crop(&path) {
            assert_eq!((crop.region, crop.frame), (region, frame), "header and pixels agree");
            let merged = merge(&[(path.clone(), crop)]);
            assert_eq!(merged.is_ok(), tiles, "merge agrees with the header check");
        }
    }
});
