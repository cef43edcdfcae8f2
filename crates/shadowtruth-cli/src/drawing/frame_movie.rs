//! The animated error map of a run over a path (`run --frames`): every frame's error map, drawn
//! as the run's error figure is (`figures.rs`), shrunk to at most [`MOVIE_WIDTH`] pixels wide with
//! its legend drawn again at that size, and appended to `figures/<run stem>.frames.png`, an APNG
//! in the figures' palette (`indexed_image.rs`).
//!
//! Frames are encoded as they arrive, so that a long path never holds more than one frame per
//! run: each run's file stays open from its first frame to its last, then is renamed into place,
//! so that a killed run leaves no half-written animation (as `src/atomic_file.rs` does for every
//! other file).

use super::figures::{
    FALSE_LIT_INDEX, FALSE_SHADOW_INDEX, LEGEND_BACKGROUND, LEGEND_TEXT, UNCERTAIN_INDEX, ViewCanvas,
    downscale, error_map_unlabelled, legend_scale, legend_strip_height, run_stem, view_stem,
};
use super::indexed_image::IndexedImage;
use super::palette::palette_bytes;
use super::text;
use crate::plan::TracedView;
use shadowtruth::record::RunRecord;
use shadowtruth::trace::{GBuffer, HardReference};
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Widest frame of an animated error map, in pixels: small enough for a page of them.
pub const MOVIE_WIDTH: u32 = 480;

/// Each frame shows for 1/10 s: a 40-frame path plays in 4 s.
const FRAME_DELAY: (u16, u16) = (1, 10);

/// The file under `figures/` of a run's animated error map.
pub fn movie_file_name(run_stem: &str) -> String {
    format!("{run_stem}.frames.png")
}

/// One frame of the animation: the frame's error map shrunk by the least integer factor that
/// makes it at most [`MOVIE_WIDTH`] wide (`downscale` keeps error pixels visible), over a legend
/// strip drawn at the small size so that its text stays readable.
pub fn movie_frame(
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    canvas: &ViewCanvas,
    (frame, frames): (u32, u32),
) -> IndexedImage {
    let (mut map, false_shadow, false_lit) = error_map_unlabelled(gbuffer, reference, visibility, canvas);
    map.pixels.truncate(gbuffer.width as usize * gbuffer.height as usize);
    map.height = gbuffer.height;
    let small = downscale(&map, gbuffer.width.div_ceil(MOVIE_WIDTH).max(1));
    let strip = legend_strip_height(small.width);
    let mut out = IndexedImage::filled(small.width, small.height + strip, LEGEND_BACKGROUND);
    out.pixels[..small.pixels.len()].copy_from_slice(&small.pixels);
    let evaluated = gbuffer.evaluated.len().max(1) as f64;
    let rates = [false_shadow, false_lit].map(|n| 100.0 * n as f64 / evaluated);
    draw_frame_legend(&mut out, small.height, rates, canvas.uncertain(), (frame, frames));
    out
}

/// The legend of one frame: the two error colours (false shadow, false lit) with their rates,
/// the uncertain colour with its pixels when the frame has any, and the frame's index over the
/// last one's (from 0, as report.json's `temporal.worst_frame` counts), short enough for a
/// shrunk frame.
fn draw_frame_legend(
    img: &mut IndexedImage,
    top: u32,
    [fs, fl]: [f64; 2],
    uncertain: u64,
    (frame, frames): (u32, u32),
) {
    let s = legend_scale(img.width);
    let side = text::text_height(s);
    let y = (top + 4 * s) as i64;
    let mut x = (4 * s) as i64;
    let mut entries =
        vec![(FALSE_SHADOW_INDEX, format!("shadow {fs:.2}%")), (FALSE_LIT_INDEX, format!("lit {fl:.2}%"))];
    if uncertain > 0 {
        entries.push((UNCERTAIN_INDEX, format!("uncertain {uncertain}")));
    }
    for (index, label) in entries {
        img.fill_rect(x, y, side, side, index);
        x += (side + 3 * s) as i64;
        img.draw_text(x, y, &label, s, LEGEND_TEXT);
        x += (text::text_width(&label, s) + 10 * s) as i64;
    }
    img.draw_text(x, y, &format!("frame {frame}/{}", frames.saturating_sub(1)), s, LEGEND_TEXT);
}

/// An APNG being written: its frames so far in a locked temporary file beside `path`.
struct Movie {
    png: png::Writer<BufWriter<File>>,
    temp: NamedTempFile,
    path: PathBuf,
    size: (u32, u32),
    frames: u32,
    written: u32,
}

impl Movie {
    /// An animation of `frames` frames of `size` pixels, playing in a loop, in the palette of
    /// every figure (indexed, the `Sub` filter and quick deflate, as `IndexedImage::encode_png`).
    fn create(path: &Path, size: (u32, u32), frames: u32) -> std::io::Result<Movie> {
        let temp = shadowtruth::atomic_file::temp_file_for(path)?;
        let file = BufWriter::new(temp.as_file().try_clone()?);
        let mut encoder = png::Encoder::new(file, size.0, size.1);
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_palette(palette_bytes());
        encoder.set_deflate_compression(png::DeflateCompression::Level(1));
        encoder.set_filter(png::Filter::Sub);
        encoder.set_animated(frames, 0).map_err(std::io::Error::other)?;
        encoder.set_frame_delay(FRAME_DELAY.0, FRAME_DELAY.1).map_err(std::io::Error::other)?;
        let png = encoder.write_header().map_err(std::io::Error::other)?;
        Ok(Movie { png, temp, path: path.to_path_buf(), size, frames, written: 0 })
    }

    fn append(&mut self, image: &IndexedImage) -> std::io::Result<()> {
        if (image.width, image.height) != self.size {
            return Err(self.error(format!(
                "frame {} is {}×{}, the first was {}×{}",
                self.written, image.width, image.height, self.size.0, self.size.1
            )));
        }
        self.png.write_image_data(&image.pixels).map_err(std::io::Error::other)?;
        self.written += 1;
        Ok(())
    }

    /// Ends the PNG and renames it into place. Unsynced, as every figure (`indexed_image.rs`):
    /// a rerun draws it again.
    fn finish(self) -> std::io::Result<()> {
        self.png.finish().map_err(std::io::Error::other)?;
        shadowtruth::atomic_file::persist(self.temp, &self.path)
    }

    fn error(&self, what: String) -> std::io::Error {
        std::io::Error::other(format!("{}: {what}", self.path.display()))
    }
}

/// The animations of the runs over a path, one open file per run between its first frame and
/// its last.
pub struct FrameMovies {
    dir: PathBuf,
    open: HashMap<String, Movie>,
    /// The canvas of the frame drawn last, with its view's stem and frame index: every run of a
    /// frame shares it, so it is built once per frame rather than once per run.
    canvas: Option<(String, u32, ViewCanvas)>,
}

impl FrameMovies {
    /// Animations into `figures_dir`.
    pub fn new(figures_dir: &Path) -> Self {
        FrameMovies { dir: figures_dir.to_path_buf(), open: HashMap::new(), canvas: None }
    }

    /// Draws one frame of a run (`Event::FrameDone`) and appends it to the run's animation; the
    /// run's last frame finishes the file.
    pub fn frame_done(
        &mut self,
        view: &TracedView,
        record: &RunRecord,
        visibility: &[f32],
        (frame, frames): (u32, u32),
    ) -> std::io::Result<()> {
        let reference = view.references.for_kind(record.reference.kind).0;
        let image = {
            let canvas = self.canvas_for(view, frame);
            movie_frame(view.gbuffer, reference, visibility, canvas, (frame, frames))
        };
        self.append(&run_stem(record), (frame, frames), &image)
    }

    /// The canvas of `view` at `frame`, built unless it is the one of the frame drawn last.
    fn canvas_for(&mut self, view: &TracedView, frame: u32) -> &ViewCanvas {
        let stem = view_stem(view.key());
        let size = (view.gbuffer.width, view.gbuffer.height);
        let cached = self
            .canvas
            .as_ref()
            .is_some_and(|(s, f, c)| *s == stem && *f == frame && (c.base.width, c.base.height) == size);
        if !cached {
            let canvas = ViewCanvas::new(view.gbuffer, &view.references.hard, view.light);
            self.canvas = Some((stem, frame, canvas));
        }
        &self.canvas.as_ref().expect("just set").2
    }

    /// The shaded base image of the frame drawn last, when it is of the view `view_stem` and
    /// `width`×`height` (what a heat map of a still camera is drawn over).
    pub fn last_base(&self, view_stem: &str, (width, height): (u32, u32)) -> Option<&IndexedImage> {
        let (stem, _, canvas) = self.canvas.as_ref()?;
        (stem == view_stem && (canvas.base.width, canvas.base.height) == (width, height))
            .then_some(&canvas.base)
    }

    /// Appends frame `frame` of `frames` to the animation of run `stem`: frame 0 opens it, the
    /// last finishes it. Frames of a run arrive in order (`src/plan/events.rs`); any other
    /// order is an error rather than a wrong animation.
    pub fn append(
        &mut self,
        stem: &str,
        (frame, frames): (u32, u32),
        image: &IndexedImage,
    ) -> std::io::Result<()> {
        if frame == 0 {
            let path = self.dir.join(movie_file_name(stem));
            self.open.insert(stem.to_string(), Movie::create(&path, (image.width, image.height), frames)?);
        }
        let movie = self.open.get_mut(stem).ok_or_else(|| {
            std::io::Error::other(format!("{}: frame {frame} came before frame 0", movie_file_name(stem)))
        })?;
        if (movie.written, movie.frames) != (frame, frames) {
            let expected = format!("frame {} of {}", movie.written, movie.frames);
            let error = movie.error(format!("frame {frame} of {frames} came instead of {expected}"));
            self.open.remove(stem);
            return Err(error);
        }
        movie.append(image)?;
        if movie.written == frames {
            self.open.remove(stem).expect("open").finish()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::figures::is_grey;
    use glam::Vec3;
    use shadowtruth::scene::{Camera, Light, LightKind, PixelFootprint};
    use shadowtruth::trace::PixelClass;

    /// A `width`×`height` G-buffer whose every pixel is evaluated, facing up at a light straight
    /// above, with a reference lit on its left half.
    fn flat_view(width: u32, height: u32) -> (GBuffer, HardReference, Light) {
        let n = (width * height) as usize;
        let gbuffer = GBuffer {
            width,
            height,
            class: vec![PixelClass::Evaluated; n],
            position: vec![Vec3::ZERO; n],
            barycentric: vec![[0.0; 2]; n],
            normal: vec![Vec3::Y; n],
            triangle: vec![0; n],
            evaluated: (0..n as u32).collect(),
            footprint: PixelFootprint::of(&Camera {
                name: "c".into(),
                position: Vec3::Z,
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 60.0,
                width,
                height,
                path: None,
            }),
        };
        let lit = (0..n).map(|i| ((i as u32 % width) < width / 2) as u8).collect();
        let reference = HardReference { width, height, lit, uncertain: Vec::new() };
        let kind = LightKind::Directional { direction: -Vec3::Y, angular_diameter_deg: None };
        (gbuffer, reference, Light { name: "sun".into(), kind, path: None, cascades: None })
    }

    /// Decodes an APNG: its declared frame count and each frame's size.
    fn decode_frames(path: &Path) -> (u32, Vec<(u32, u32)>) {
        let decoder = png::Decoder::new(std::io::BufReader::new(File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let declared = reader.info().animation_control.expect("an APNG").num_frames;
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let mut sizes = Vec::new();
        while let Ok(info) = reader.next_frame(&mut buf) {
            sizes.push((info.width, info.height));
        }
        (declared, sizes)
    }

    #[test]
    fn the_animation_has_every_frame_at_the_shrunk_size() {
        let dir = tempfile::tempdir().unwrap();
        let (gbuffer, reference, light) = flat_view(1000, 40);
        let canvas = ViewCanvas::new(&gbuffer, &reference, &light);
        let frames = 5;
        let mut movies = FrameMovies::new(dir.path());
        for frame in 0..frames {
            // A technique that gets more of the left half wrong in every frame.
            let wrong = (frame * 100) as usize;
            let visibility: Vec<f32> = (0..gbuffer.evaluated.len())
                .map(|i| if i % 1000 < wrong { 0.0 } else { reference.lit[i] as f32 })
                .collect();
            let image = movie_frame(&gbuffer, &reference, &visibility, &canvas, (frame, frames));
            assert!(image.width <= MOVIE_WIDTH);
            let area = (image.width * (40 / 3)) as usize;
            assert_eq!(image.pixels[..area].iter().any(|&p| !is_grey(p)), frame > 0, "frame {frame}");
            // Two runs interleaved, as the frames of a path reach every run of a frame in turn.
            movies.append("a", (frame, frames), &image).unwrap();
            movies.append("b", (frame, frames), &image).unwrap();
            assert_eq!(dir.path().join(movie_file_name("a")).is_file(), frame + 1 == frames);
        }
        // 1000 pixels shrink by 3 to 333; the legend strip is drawn at that width.
        let size = (333, 40 / 3 + legend_strip_height(333));
        for stem in ["a", "b"] {
            let (declared, sizes) = decode_frames(&dir.path().join(movie_file_name(stem)));
            assert_eq!(declared, frames);
            assert_eq!(sizes, vec![size; frames as usize]);
        }
        // Only the two animations are left: no temporary file.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn frames_out_of_order_are_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let mut movies = FrameMovies::new(dir.path());
        let image = IndexedImage::filled(4, 3, 9);
        assert!(movies.append("a", (1, 3), &image).is_err());
        movies.append("a", (0, 3), &image).unwrap();
        assert!(movies.append("a", (2, 3), &image).is_err());
        movies.append("b", (0, 2), &image).unwrap();
        assert!(movies.append("b", (1, 2), &IndexedImage::filled(5, 3, 9)).is_err());
        drop(movies);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "unfinished animations are removed");
    }
}
