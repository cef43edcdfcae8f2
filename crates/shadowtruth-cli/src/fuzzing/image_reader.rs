//! The image reader: bytes read as an EXR and as a PNG, visibility and depth, with and without
//! an expected size, from memory through the code that reads image files (src/import/read.rs).

use shadowtruth::import::{
    ExpectedSize, ImageSource, ImportedImage, ReadOptions, read_depth_from, read_visibility_from,
};
use std::path::Path;

/// Images a fuzzed header may declare without an expected size: the bound is checked by the
/// same code as the tool's (src/import/expected_size.rs tests those), at a size that keeps each
/// input fast.
const FUZZ_UNKNOWN_SIZE: ExpectedSize =
    ExpectedSize::AtMost { side: 64, pixels: 4096, largest: "fuzzed image" };

/// The size the seeds of fuzz/corpus/image_reader/ mostly have.
const FUZZ_VIEW: ExpectedSize = ExpectedSize::View { width: 4, height: 3 };

/// Reads `data` every way an imported image is read; whatever reads must hold its promises.
pub fn image_reader(data: &[u8]) {
    for name in ["fuzz.exr", "fuzz.png"] {
        let name = Path::new(name);
        for expected in [FUZZ_VIEW, FUZZ_UNKNOWN_SIZE] {
            let source = ImageSource::Bytes { name, bytes: data };
            let options = ReadOptions::default();
            if let Ok(image) = read_visibility_from(source, &options, expected) {
                check_image(&image, expected);
                assert!(image.values.iter().all(|v| v.is_nan() || *v <= 1.0), "a visibility above 1");
            }
            let flipped = ReadOptions { flip_y: true, ..ReadOptions::default() };
            if let Ok(image) = read_depth_from(source, &flipped, expected) {
                check_image(&image, expected);
                assert!(image.values.iter().all(|d| *d >= 0.0), "a NaN or negative depth");
            }
        }
    }
}

/// One value per declared pixel, of the expected size.
fn check_image(image: &ImportedImage, expected: ExpectedSize) {
    assert_eq!(image.values.len(), image.width as usize * image.height as usize);
    assert!(expected.check(image.width as u64, image.height as u64).is_ok(), "a size that was not expected");
}
