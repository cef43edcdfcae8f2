//! Figures: the error map's colours count exactly the scored false pixels, the colours are
//! distinct from each other and from the shaded greys, grids and zooms have the promised
//! geometry, and run stems are unique and file-name safe.

use super::common;

use crate::drawing::figures::{
    FALSE_LIT_INDEX, FALSE_SHADOW_INDEX, GRID_BACKGROUND, GRID_GAP, GRID_TEXT, GridCell, GridLayout,
    ViewCanvas, ZOOM_FRAME, caption_block_height, error_map, grid, is_grey, legend_strip_height,
    reference_visibility, run_images, run_stem, view_stem, visibility_image, write_reference_figure,
    write_run_figures, zoom,
};
use crate::drawing::indexed_image::IndexedImage;
use crate::drawing::palette::{FALSE_LIT, FALSE_SHADOW, UNCERTAIN};
use crate::drawing::text;
use common::{bundled, trace_first};
use shadowtruth::metrics::{Counts, Rates};
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{RunRecord, Timings};
use shadowtruth::scene::ViewKey;
use shadowtruth::technique::{ConstantParams, CullSpec, NoneParams, SlopeScaledParams, TechniqueSpec};
use std::collections::HashSet;

fn techniques() -> [TechniqueSpec; 2] {
    [
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.05) }),
    ]
}

fn count_colour(pixels: &[u8], colour: [u8; 3]) -> u64 {
    pixels.chunks_exact(3).filter(|p| *p == colour).count() as u64
}

#[test]
fn error_png_colours_count_exactly_the_false_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let (mut any_false_shadow, mut any_false_lit, mut any_uncertain) = (false, false, false);
    for name in ["plane_box", "spot"] {
        let scene = bundled(name);
        let (g, r) = trace_first(&scene);
        let canvas = ViewCanvas::new(&g, &r, &scene.lights[0]);
        let reference_file = write_reference_figure(dir.path(), name, &g, &r, &canvas).unwrap();
        assert_eq!(reference_file, format!("{name}.reference.png"));
        let reference = image::open(dir.path().join(&reference_file)).unwrap().to_rgb8();
        assert_eq!(
            reference.as_raw(),
            &visibility_image(&g, &canvas, &reference_visibility(&g, &r)).to_rgb()
        );
        for spec in techniques() {
            let (counts, v) = common::score_technique(&scene, &g, &r, &spec, 512, DepthFormat::F32);
            let stem = format!("{name}.{}", spec.name());
            let files = write_run_figures(dir.path(), &stem, &g, &r, &v, &canvas).unwrap();
            assert_eq!(files.error, format!("{stem}.error.png"));
            assert_eq!(files.technique, format!("{stem}.technique.png"));

            let error = image::open(dir.path().join(&files.error)).unwrap().to_rgb8();
            let strip = legend_strip_height(g.width);
            assert_eq!(error.dimensions(), (g.width, g.height + strip), "{name} {spec:?}");
            let (area, legend) = error.as_raw().split_at((g.width * g.height * 3) as usize);
            let what = format!("{name} {}: {counts:?}", spec.label());
            assert_eq!(count_colour(area, FALSE_SHADOW), counts.false_shadow, "{what}");
            assert_eq!(count_colour(area, FALSE_LIT), counts.false_lit, "{what}");
            // The pixels the reference cannot decide (spot's view has some) in their own colour.
            assert_eq!(count_colour(area, UNCERTAIN), counts.uncertain, "{what}");
            // Everything else in the image area is a (dimmed) grey, so no other pixel can be
            // mistaken for an error; the legend shows the three swatches.
            for p in area.chunks_exact(3) {
                let coloured = p == FALSE_SHADOW || p == FALSE_LIT || p == UNCERTAIN;
                assert!(coloured || (p[0] == p[1] && p[1] == p[2]), "{p:?}");
            }
            assert!(count_colour(legend, FALSE_SHADOW) > 0 && count_colour(legend, FALSE_LIT) > 0);
            assert!(count_colour(legend, UNCERTAIN) > 0, "{what}: no uncertain swatch");
            // The in-memory map is what was written.
            assert_eq!(error_map(&g, &r, &v, &canvas).to_rgb(), error.as_raw().as_slice());
            // The one-pass drawing of both images is the two drawn apart.
            let (t, e) = run_images(&g, &r, &v, &canvas);
            assert_eq!((t, e), (visibility_image(&g, &canvas, &v), error_map(&g, &r, &v, &canvas)));

            let technique = image::open(dir.path().join(&files.technique)).unwrap().to_rgb8();
            assert_eq!(technique.dimensions(), (g.width, g.height));
            assert_eq!(technique.as_raw(), &visibility_image(&g, &canvas, &v).to_rgb());
            any_false_shadow |= counts.false_shadow > 0;
            any_false_lit |= counts.false_lit > 0;
            any_uncertain |= counts.uncertain > 0;
        }
    }
    assert!(any_false_shadow && any_false_lit, "the runs must exercise both colours");
    assert!(any_uncertain, "the runs must exercise the uncertain colour");
}

/// Viénot, Brettel & Mollon (1999) dichromat simulation in linear RGB.
fn simulate(colour: [u8; 3], m: [[f32; 3]; 3]) -> [f32; 3] {
    let lin = |c: u8| {
        let c = c as f32 / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    let l = colour.map(lin);
    let enc = |c: f32| {
        let c = c.clamp(0.0, 1.0);
        255.0 * if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
    };
    [0, 1, 2].map(|i| enc(m[i][0] * l[0] + m[i][1] * l[1] + m[i][2] * l[2]))
}

#[test]
fn error_colours_are_distinct_from_each_other_and_from_every_base_grey() {
    assert_ne!(FALSE_SHADOW, FALSE_LIT);
    let protan = [[0.11238, 0.88762, 0.0], [0.11238, 0.88762, 0.0], [0.00401, -0.00401, 1.0]];
    let deutan = [[0.29275, 0.70725, 0.0], [0.29275, 0.70725, 0.0], [-0.02234, 0.02234, 1.0]];
    for (name, m) in [("protanopia", protan), ("deuteranopia", deutan)] {
        let (a, b) = (simulate(FALSE_SHADOW, m), simulate(FALSE_LIT, m));
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        assert!(d > 100.0, "{name}: {a:?} vs {b:?} are too close ({d})");
    }
    for name in ["plane_box", "spot"] {
        let scene = bundled(name);
        let (g, r) = trace_first(&scene);
        let canvas = ViewCanvas::new(&g, &r, &scene.lights[0]);
        let base = &canvas.base;
        let reference = visibility_image(&g, &canvas, &crate::drawing::figures::reference_visibility(&g, &r));
        let mut greys = HashSet::new();
        for img in [base, &reference] {
            for p in img.to_rgb().chunks_exact(3) {
                assert!(p[0] == p[1] && p[1] == p[2], "{name}: base pixel {p:?} is not grey");
                assert!(p != FALSE_SHADOW && p != FALSE_LIT);
                greys.insert(p[0]);
            }
            assert!(img.pixels.iter().all(|&i| is_grey(i)));
        }
        assert!(greys.len() >= 4, "{name}: the shaded image has only {} grey levels", greys.len());
        // Background dark, evaluated light, facing away darker than evaluated.
        let level = |cls| {
            let (sum, n) = g
                .class
                .iter()
                .enumerate()
                .filter(|(_, c)| **c == cls)
                .fold((0u64, 0u64), |(s, n), (i, _)| (s + base.pixels[i] as u64, n + 1));
            sum as f64 / n.max(1) as f64
        };
        use shadowtruth::trace::PixelClass;
        assert!(level(PixelClass::Background) < 60.0);
        assert!(level(PixelClass::Evaluated) > 150.0);
        if g.count(PixelClass::FacingAway) > 0 {
            assert!(level(PixelClass::FacingAway) < level(PixelClass::Evaluated) - 40.0);
        }
    }
}

/// The caption band of a grid cell, `width`×`height` pixels of the page, with `caption` drawn
/// alone where the grid promises it: centred, its box two pixels below the image.
fn caption_alone(caption: &str, (width, height): (u32, u32)) -> IndexedImage {
    let mut band = IndexedImage::filled(width, height, GRID_BACKGROUND);
    let x = (width.saturating_sub(text::text_width(caption, 1)) / 2) as i64;
    band.draw_text(x, 2, caption, 1, GRID_TEXT);
    band
}

#[test]
fn grid_of_two_by_three_cells_has_its_size_and_captions() {
    let levels: Vec<u8> = vec![40, 70, 100, 130, FALSE_SHADOW_INDEX, FALSE_LIT_INDEX];
    let images: Vec<IndexedImage> = levels.iter().map(|&c| IndexedImage::filled(160, 120, c)).collect();
    let cells: Vec<GridCell> = images
        .iter()
        .enumerate()
        .map(|(k, img)| GridCell { image: img, caption: format!("cell {k} err 1.{k}%") })
        .collect();
    let out = grid(&cells, 3, 400);
    let (w, h) = (out.width, out.height);
    // Three columns of 160 and two rows of 120 + one caption line at scale 1, 4-pixel gaps.
    assert_eq!(GRID_GAP, 4);
    assert_eq!(caption_block_height(1, 1), 12);
    assert_eq!((w, h), (3 * 160 + 4 * 4, 2 * (120 + 12) + 3 * 4));
    assert_eq!(out.pixels.len(), (w * h) as usize);
    for (k, cell) in cells.iter().enumerate() {
        let (x0, y0) = (4 + (k as u32 % 3) * 164, 4 + (k as u32 / 3) * 136);
        for y in y0..y0 + 120 {
            for x in x0..x0 + 160 {
                assert_eq!(out.at(x, y), levels[k], "cell {k} at ({x}, {y})");
            }
        }
        // The band under the cell is its caption and nothing else, pixel for pixel.
        let expected = caption_alone(&cell.caption, (160, 12));
        let inked = expected.pixels.iter().filter(|&&p| p != GRID_BACKGROUND).count();
        let visible = cell.caption.chars().filter(|c| *c != ' ').count();
        assert!(inked > 5 * visible, "cell {k}: {inked} inked pixels for {visible} characters");
        assert!(expected.pixels.iter().any(|&p| p < GRID_BACKGROUND / 2), "cell {k}: the text is dark");
        for y in 0..12 {
            for x in 0..160 {
                assert_eq!(
                    out.at(x0 + x, y0 + 120 + y),
                    expected.at(x, y),
                    "cell {k}'s caption at ({x}, {y})"
                );
            }
        }
        // Each caption is its own text, not a copy of its neighbour's.
        if k > 0 {
            assert_ne!(expected, caption_alone(&cells[k - 1].caption, (160, 12)), "cell {k}");
        }
    }
    // The gaps are background.
    for y in 0..h {
        assert_eq!(out.at(164, y), GRID_BACKGROUND);
    }

    // Large cells are shrunk by an integer factor: greys by a box filter, and an error pixel
    // anywhere in a block keeps the block in its colour.
    let mut stripes = IndexedImage {
        width: 640,
        height: 480,
        pixels: (0..480 * 640).map(|i| if i % 2 == 0 { 0 } else { 200 }).collect(),
    };
    stripes.pixels[(101 * 640 + 41) as usize] = FALSE_LIT_INDEX;
    let big = [
        GridCell { image: &stripes, caption: "a".into() },
        GridCell { image: &stripes, caption: "b".into() },
    ];
    let layout = GridLayout::new(&big, 2, 320);
    assert_eq!((layout.downscale, layout.cell_width, layout.cell_height), (2, 320, 240));
    let out = grid(&big, 2, 320);
    assert_eq!((out.width, out.height), (layout.width, layout.height));
    assert_eq!((out.width, out.height), (2 * 320 + 3 * 4, 240 + caption_block_height(1, 1) + 2 * 4));
    assert_eq!(out.at(4 + 10, 4 + 10), 100, "the mean of a 2×2 block of alternating columns");
    assert_eq!(out.at(4 + 20, 4 + 50), FALSE_LIT_INDEX, "the block holding the false-lit pixel");
    assert_eq!(out.at(4 + 21, 4 + 50), 100);
}

#[test]
fn zoom_repeats_the_source_pixels_inside_a_frame() {
    let (w, h) = (64u32, 48u32);
    let src = IndexedImage {
        width: w,
        height: h,
        pixels: (0..h).flat_map(|y| (0..w).map(move |x| ((x * 3 + y) % 250) as u8)).collect(),
    };
    let rect = (10, 5, 7, 4);
    let scale = 3;
    let out = zoom(&src, rect, scale);
    let (zw, zh) = (out.width, out.height);
    assert_eq!((zw, zh), (7 * 3 + 2, 4 * 3 + 2));
    for y in 0..zh {
        for x in 0..zw {
            let got = out.at(x, y);
            if x == 0 || y == 0 || x == zw - 1 || y == zh - 1 {
                assert_eq!(got, ZOOM_FRAME, "frame at ({x}, {y})");
            } else {
                let (sx, sy) = (rect.0 + (x - 1) / scale, rect.1 + (y - 1) / scale);
                assert_eq!(got, src.at(sx, sy), "({x}, {y}) shows source ({sx}, {sy})");
            }
        }
    }
}

fn record(
    scene: &str,
    camera: &str,
    light: &str,
    spec: &TechniqueSpec,
    resolution: u32,
    format: &str,
) -> RunRecord {
    RunRecord {
        scene: scene.into(),
        camera: camera.into(),
        light: light.into(),
        technique: spec.name().into(),
        parameters: spec.parameters(),
        label: spec.label(),
        resolution,
        depth_format: format.into(),
        counts: Counts::default(),
        rates: Rates::default(),
        timings: Timings::default(),
        layer_memory_bytes: 0,
        reference: Default::default(),
        soft: None,
        pipeline: None,
        cascades: None,
        point_map: None,
        temporal: None,
    }
}

#[test]
fn run_stems_are_unique_and_file_name_safe() {
    let specs = [
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(0.001), bias_world: None }),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(0.0001), bias_world: None }),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(-0.001), bias_world: None }),
        TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.001) }),
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.5, units: 2.0, cull: CullSpec::None }),
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.5, units: 2.0, cull: CullSpec::Back }),
    ];
    let mut records = Vec::new();
    for scene in ["plane_box", "plane box", "plane/box", "plane(box)", "Ébène", ".hidden"] {
        for camera in ["main", "top"] {
            for light in ["sun", "lamp"] {
                for spec in &specs {
                    for resolution in [512, 1024] {
                        for format in ["f32", "unorm16"] {
                            records.push(record(scene, camera, light, spec, resolution, format));
                        }
                    }
                }
            }
        }
    }
    let stems: HashSet<String> = records.iter().map(run_stem).collect();
    assert_eq!(stems.len(), records.len(), "every key gives its own stem");
    for stem in &stems {
        assert!(
            stem.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')),
            "{stem:?} has a character unsafe in file names"
        );
        assert!(!stem.starts_with(['.', '-']), "{stem:?}");
        assert!(stem.len() <= 200, "{stem:?}");
    }
    // View stems (reference figures) likewise.
    let views: Vec<(&str, &str, &str)> = vec![
        ("plane_box", "main", "sun"),
        ("plane box", "main", "sun"),
        ("plane_box", "main", "lamp"),
        ("plane_box", "top", "sun"),
        ("plane", "box.main", "sun"),
    ];
    let view_stems: HashSet<String> =
        views.iter().map(|(s, c, l)| view_stem(ViewKey::new(s, c, l))).collect();
    assert_eq!(view_stems.len(), views.len());
    assert!(view_stem(ViewKey::new("plane_box", "main", "sun")).starts_with("plane_box.main.sun."));
    for stem in &view_stems {
        assert!(stem.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')), "{stem:?}");
    }
    let r = record("plane_box", "main", "sun", &specs[1], 1024, "f32");
    let stem = run_stem(&r);
    assert_eq!(stem, run_stem(&r.clone()), "stable");
    assert!(stem.starts_with("plane_box.main.sun.constant_bias_depth-0.001.r1024.f32."), "readable: {stem}");
}

/// Median milliseconds of 7 calls of `f`.
fn median_ms(f: impl FnMut()) -> f64 {
    shadowtruth::metrics::timed_median(7, f).1
}

/// Prints the cost of one run's figures at 1024×768 beside the cost of the run's shading pass
/// (run with `--nocapture`).
#[test]
fn figures_cost_per_run_at_1024x768() {
    use shadowtruth::technique::{ShadeContext, ShadeOrder, shade_evaluated};
    let scene = bundled("plane_box");
    let (g, r) = trace_first(&scene);
    assert_eq!((g.width, g.height), (1024, 768));
    let canvas_ms = median_ms(|| drop(std::hint::black_box(ViewCanvas::new(&g, &r, &scene.lights[0]))));
    let canvas = ViewCanvas::new(&g, &r, &scene.lights[0]);

    // One shading pass of the plain depth test with a 2048² layer (what every run repeats).
    let technique = TechniqueSpec::None(NoneParams {}).build().expect("a shaded technique");
    let view = shadowtruth::raster::LightView::new(&scene.lights[0], scene.bounds(), 2048);
    let layers =
        shadowtruth::technique::BuiltLayers::build(&scene, &view, DepthFormat::F32, &technique.layer_needs());
    let ctx = ShadeContext::new(&scene, g.footprint, &view, layers.as_layers());
    let order = ShadeOrder::new(&g, &view);
    let shade_ms =
        median_ms(|| drop(std::hint::black_box(shade_evaluated(technique.as_ref(), &order, &ctx))));
    let v = shade_evaluated(technique.as_ref(), &order, &ctx);

    let dir = tempfile::tempdir().unwrap();
    let mut k = 0;
    let figures_ms = median_ms(|| {
        write_run_figures(dir.path(), &format!("run{k}"), &g, &r, &v, &canvas).unwrap();
        k += 1;
    });
    let bytes: u64 = ["run0.technique.png", "run0.error.png"]
        .iter()
        .map(|f| std::fs::metadata(dir.path().join(f)).unwrap().len())
        .sum();
    // Where the time goes (each step alone): the two images, their PNG encoding.
    let images_ms = median_ms(|| drop(std::hint::black_box(run_images(&g, &r, &v, &canvas))));
    let tech = visibility_image(&g, &canvas, &v);
    let err = error_map(&g, &r, &v, &canvas);
    let encode_ms = median_ms(|| {
        std::hint::black_box(tech.encode_png().unwrap());
        std::hint::black_box(err.encode_png().unwrap());
    });
    println!(
        "figures 1024x768 ({} threads): write_run_figures {figures_ms:.1} ms per run ({} KiB; images \
         {images_ms:.1} ms + PNG encoding {encode_ms:.1} ms when run one after the other); the view's \
         canvas {canvas_ms:.1} ms once per view; one shading pass of `none` at 2048² {shade_ms:.1} ms",
        rayon::current_num_threads(),
        bytes / 1024,
    );
}
