//! The same loop as `wgsl_integration`, on the CPU only: a renderer's
//! frame, then `sampler_core::permute_frame` to get the next frame's seeds.
//! `cargo run -p shader-sources --example cpu_permute`.

use sampler_core::{defaults, initial_seed, permute_frame, FrameLayout};

const WIDTH: u32 = 256;
const HEIGHT: u32 = 160;

/// The scene: a disc over a gradient.
fn truth(x: u32, y: u32) -> f32 {
    let (u, v) = ((x as f32 + 0.5) / WIDTH as f32, (y as f32 + 0.5) / HEIGHT as f32);
    if ((u - 0.5).powi(2) + (v - 0.5).powi(2)).sqrt() < 0.3 {
        0.25
    } else {
        u
    }
}

/// One sample per pixel from the pixel's seed alone.
fn render(seeds: &[u32], padded_width: u32) -> Vec<f32> {
    (0..WIDTH * HEIGHT)
        .map(|i| {
            let (x, y) = (i % WIDTH, i / WIDTH);
            let u = sampler_core::random_f32(seeds[(y * padded_width + x) as usize], 0);
            if u < truth(x, y) {
                1.0
            } else {
                0.0
            }
        })
        .collect()
}

/// RMS of the error averaged over 3x3 pixels (what the eye sees).
fn blurred_error(image: &[f32]) -> f32 {
    let mut sum = 0.0;
    for y in 1..HEIGHT - 1 {
        for x in 1..WIDTH - 1 {
            let mut e = 0.0;
            for (dx, dy) in (0..3).flat_map(|dy| (0..3).map(move |dx| (dx, dy))) {
                let (px, py) = (x + dx - 1, y + dy - 1);
                e += image[(py * WIDTH + px) as usize] - truth(px, py);
            }
            sum += (e / 9.0).powi(2);
        }
    }
    (sum / ((WIDTH - 2) * (HEIGHT - 2)) as f32).sqrt()
}

fn main() -> Result<(), sampler_core::Error> {
    println!("device: CPU (sampler_core::permute_frame)");
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64)?;
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let pw = layout.padded_width();
    // Frame 0: white-noise seeds over the padded buffer.
    let mut seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i % pw, i / pw, pw, 0))
        .collect();
    let mut next = vec![0; seeds.len()];
    for frame in 0..8 {
        let image = render(&seeds, pw);
        println!("frame {frame}: blurred error {:.4}", blurred_error(&image));
        // Sort this frame's seeds by its image, retarget them for the next frame.
        permute_frame(&layout, frame, &image, &tile, &tables, &seeds, &mut next)?;
        std::mem::swap(&mut seeds, &mut next);
    }
    Ok(())
}
