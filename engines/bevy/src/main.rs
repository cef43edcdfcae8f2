//! `shadowtruth-bevy`: renders a `shadowtruth view-export` folder with Bevy 0.16's own shadow
//! maps and shadow sampling, headless (Vulkan; lavapipe where there is no GPU), and writes what
//! `shadowtruth score` reads. See README.md.

mod cascade;
mod material;
mod options;
mod output;
mod render;
mod scene;
mod view;

use clap::Parser;
use std::panic::AssertUnwindSafe;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args = options::Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("shadowtruth-bevy: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(args: &options::Args) -> Result<(), String> {
    let started = Instant::now();
    let (view, glb) = view::read(&args.view)?;
    let spot = matches!(view.light, view::Light::Spot { .. });
    let settings = args.settings(view.light.shadow_map().resolution, spot)?;
    let objects = scene::read(&glb)?;
    let (width, height) = (view.camera.width, view.camera.height);
    // Bevy panics where it cannot start (no Vulkan adapter, a shader that does not compile); its
    // panic hook has printed the cause, this adds what to check and the exit status.
    let rendered = std::panic::catch_unwind(AssertUnwindSafe(|| render::render(view, objects, settings)));
    let pixels = rendered.map_err(|_| {
        "Bevy stopped (see above); a Vulkan driver is needed: `apt-get install mesa-vulkan-drivers \
         libvulkan1` gives lavapipe"
            .to_string()
    })??;
    let buffers = output::decode(&pixels)?;
    if buffers.covered_pixels == 0 {
        return Err("Bevy drew no surface: the image is all background".into());
    }
    output::write_exr(&args.visibility, buffers.visibility, width, height)?;
    if let Some(depth) = &args.depth {
        output::write_exr(depth, buffers.depth_world, width, height)?;
    }
    let texel = pixels.texel_size_world.map_or(String::new(), |t| format!(" (texel {t} world)"));
    eprintln!(
        "shadowtruth-bevy: {width}×{height}, map {0}×{0}{texel}, {1:?} fit, {2:?} filter, depth bias \
         {3}, normal bias {4}: {5:.2} s",
        settings.map_size_texels,
        settings.fit,
        settings.filter,
        settings.depth_bias,
        settings.normal_bias,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
