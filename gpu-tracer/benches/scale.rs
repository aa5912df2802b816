//! Scale: CPU rays/s on a generated scene of more than 200k triangles beside
//! the 32-triangle Cornell box, and the BVH build time of the big scene.
//!
//! The big scene is the Cornell box (same walls, light, camera and
//! materials) with its two blocks replaced by many small objects and the
//! floor covered by a finely tessellated bumpy terrain, so paths bounce
//! much as they do in the box:
//! - a terrain heightfield of `TERRAIN_CELLS^2` cells (two triangles each)
//!   1-19 mm above the floor;
//! - a 3 x 3 x 3 stack of UV spheres (radius 27 mm) where the short block
//!   stood and a 2 x 2 x 4 stack (radius 40 mm) where the tall block stood,
//!   each sphere `SPHERE_SEGMENTS x SPHERE_RINGS` (3 968 triangles).
//!
//! Measured in one run: (a) `gpu_tracer::bvh::build_bvh` on the big scene's
//! vertex list and the whole `SceneGpu::build` (median of a few builds);
//! (b) `gpu_tracer::cpu::render_frame` at 256 x 256, 1 spp, max depth 8 on
//! 1 thread and on all cores, both scenes in interleaved rounds, rays counted
//! by the renderer (camera, continuation and shadow rays): median rays/s per
//! scene, and the median of the per-round ratios (adjacent samples, so load
//! from other processes mostly cancels); (c) traversal work per ray (nodes,
//! box and triangle tests) from a host replica of the kernels' traversal,
//! which is deterministic, and the big tree's leaf-depth histogram (the
//! kernels' stack allows leaves down to depth `kernels::bvh::STACK_SIZE`).
//! Goals (the issue): big-scene rays/s within 4x of the Cornell box's, BVH
//! build <= 1 s for 200k triangles.
//!
//! `cargo bench -p gpu-tracer --bench scale` (about 20 s after compiling on
//! 2 cores); `SCALE_TERRAIN_CELLS=700` for a 1.15M-triangle scene.

use glam::{Vec3, Vec4};
use gpu_tracer::bvh::build_bvh;
use gpu_tracer::cornell::{cornell_box, WHITE};
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::scene::{Scene, SceneGpu, TraceSettings, Triangle};
use kernels::abi::TraceParams;
use kernels::intersect::{intersect_aabb, intersect_triangle, Ray};
use std::time::{Duration, Instant};

/// Frame side in pixels.
const SIZE: u32 = 256;
/// Terrain cells per side by default (244 364 triangles in all).
const TERRAIN_CELLS: usize = 192;
/// Terrain cells per side: `TERRAIN_CELLS`, or the environment variable
/// `SCALE_TERRAIN_CELLS` (to try larger scenes: 700 gives about 1.15M
/// triangles).
fn terrain_cells() -> usize {
    std::env::var("SCALE_TERRAIN_CELLS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(TERRAIN_CELLS)
}
/// Sphere tessellation: segments around, rings pole to pole.
const SPHERE_SEGMENTS: usize = 64;
const SPHERE_RINGS: usize = 32;
/// Builds timed for the median.
const BUILDS: usize = 5;
/// Interleaved render rounds for the median.
const ROUNDS: usize = 9;
/// Lower bound of one timed render sample (whole frames are repeated).
const MIN_SAMPLE: Duration = Duration::from_millis(250);
/// Big-scene triangle count the issue asks for at least.
const MIN_TRIANGLES: usize = 200_000;

/// Terrain height above the floor at `(x, z)`, in `[1, 19]` mm.
fn terrain_height(x: f32, z: f32) -> f32 {
    10.0 + 6.0 * (x * 0.05).sin() * (z * 0.043).cos() + 3.0 * ((x + z) * 0.11).sin()
}

/// Adds triangle `[a, b, c]`, wound so its front faces away from `centre`.
fn push_outward(out: &mut Vec<Triangle>, [a, b, c]: [Vec3; 3], centre: Vec3, object: u32) {
    let normal = (b - a).cross(c - a);
    let vertices = if normal.dot((a + b + c) / 3.0 - centre) >= 0.0 {
        [a, b, c]
    } else {
        [a, c, b]
    };
    let mut t = Triangle::new(vertices, WHITE);
    t.object = object;
    out.push(t);
}

/// A UV sphere: `SPHERE_SEGMENTS * (2 * SPHERE_RINGS - 2)` triangles.
fn add_sphere(out: &mut Vec<Triangle>, centre: Vec3, radius: f32, object: u32) {
    let point = |ring: usize, seg: usize| {
        let theta = std::f32::consts::PI * ring as f32 / SPHERE_RINGS as f32;
        let phi = std::f32::consts::TAU * seg as f32 / SPHERE_SEGMENTS as f32;
        centre + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    };
    for ring in 0..SPHERE_RINGS {
        for seg in 0..SPHERE_SEGMENTS {
            let (p00, p01) = (point(ring, seg), point(ring, seg + 1));
            let (p10, p11) = (point(ring + 1, seg), point(ring + 1, seg + 1));
            if ring != 0 {
                push_outward(out, [p00, p10, p01], centre, object);
            }
            if ring + 1 != SPHERE_RINGS {
                push_outward(out, [p01, p10, p11], centre, object);
            }
        }
    }
}

/// The big scene: the Cornell box's walls, light and camera, its blocks
/// replaced by 43 tessellated spheres, and a tessellated terrain on the floor.
fn big_scene() -> Scene {
    let mut scene = cornell_box();
    // Keep the five walls and the light (the first 12 triangles, objects 0..=5).
    scene.triangles.truncate(12);
    assert!(
        scene.triangles.iter().all(|t| t.object <= 5),
        "cornell_box layout changed"
    );
    let mut object = 6;

    // Terrain over the floor, fronts facing up.
    let (x0, x1, z0, z1) = (0.5f32, 549.0f32, 0.0f32, 559.0f32);
    let n = terrain_cells();
    let p = |i: usize, j: usize| {
        let x = x0 + (x1 - x0) * i as f32 / n as f32;
        let z = z0 + (z1 - z0) * j as f32 / n as f32;
        Vec3::new(x, terrain_height(x, z), z)
    };
    for j in 0..n {
        for i in 0..n {
            let (p00, p10, p01, p11) = (p(i, j), p(i + 1, j), p(i, j + 1), p(i + 1, j + 1));
            for vertices in [[p00, p01, p10], [p10, p01, p11]] {
                let mut t = Triangle::new(vertices, WHITE);
                t.object = object;
                scene.triangles.push(t);
            }
        }
    }
    object += 1;

    // Sphere stacks where the blocks stood (footprint centres of the short
    // and tall block), resting just above the terrain's highest point.
    let stacks = [
        // (centre x, centre z, radius, per side, layers)
        (185.5f32, 168.5f32, 27.0f32, 3usize, 3usize),
        (368.5, 351.25, 40.0, 2, 4),
    ];
    for (cx, cz, r, side, layers) in stacks {
        let spacing = 2.0 * r + 1.0;
        let offset = (side as f32 - 1.0) * 0.5 * spacing;
        for layer in 0..layers {
            for a in 0..side {
                for b in 0..side {
                    let centre = Vec3::new(
                        cx - offset + a as f32 * spacing,
                        20.0 + r + layer as f32 * spacing,
                        cz - offset + b as f32 * spacing,
                    );
                    add_sphere(&mut scene.triangles, centre, r, object);
                    object += 1;
                }
            }
        }
    }
    scene
}

/// Traversal work of one ray, counted by a host replica of
/// `kernels::bvh::traverse` (same order, same culling, same primitives).
#[derive(Clone, Copy, Debug, Default)]
struct Work {
    /// Nodes popped and processed (inner and leaf).
    nodes: u64,
    /// Ray-box tests.
    boxes: u64,
    /// Ray-triangle tests.
    triangles: u64,
}

/// Closest hit of `ray` with the kernels' traversal order, counting work.
fn counted_closest_hit(gpu: &SceneGpu, ray: &Ray, work: &mut Work) -> Option<f32> {
    let nodes = &gpu.nodes;
    let inv_dir = ray.inv_dir();
    let mut best_t = f32::INFINITY;
    let mut stack: Vec<(u32, f32)> = Vec::with_capacity(64);
    let b = |n: &kernels::abi::BvhNodeGpu, best_t: f32| {
        intersect_aabb(
            ray.origin,
            inv_dir,
            n.min.truncate(),
            n.max.truncate(),
            0.0,
            best_t,
        )
    };
    work.boxes += 1;
    let mut node = b(&nodes[0], best_t).map(|_| 0u32);
    loop {
        let Some(index) = node.take() else {
            match stack.pop() {
                Some((n, t)) if t < best_t => node = Some(n),
                Some(_) => {}
                None => break,
            }
            continue;
        };
        work.nodes += 1;
        let n = nodes[index as usize];
        let (count, first) = (n.info.x, n.info.y);
        if count == 0 {
            work.boxes += 2;
            let ta = b(&nodes[first as usize], best_t);
            let tb = b(&nodes[first as usize + 1], best_t);
            match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    let (near, far, t_far) = if ta <= tb {
                        (first, first + 1, tb)
                    } else {
                        (first + 1, first, ta)
                    };
                    stack.push((far, t_far));
                    node = Some(near);
                }
                (Some(_), None) => node = Some(first),
                (None, Some(_)) => node = Some(first + 1),
                (None, None) => {}
            }
        } else {
            for i in first..first + count {
                work.triangles += 1;
                let t = gpu.triangles[i as usize];
                if let Some(h) = intersect_triangle(
                    ray,
                    t.v0.truncate(),
                    t.v1.truncate(),
                    t.v2.truncate(),
                    0.0,
                    best_t,
                ) {
                    best_t = h.t;
                }
            }
        }
    }
    (best_t < f32::INFINITY).then_some(best_t)
}

/// Mean traversal work per ray over camera rays through the centres of a
/// `SIZE x SIZE` frame and one uniformly random direction from each camera
/// hit (a stand-in for bounce rays): `(camera, bounce)`.
fn traversal_work(gpu: &SceneGpu) -> (Work, Work, u64) {
    let cam = gpu.camera;
    let (mut primary, mut bounce, mut bounces) = (Work::default(), Work::default(), 0u64);
    let mut state = 0x9e37_79b9u32;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    for y in 0..SIZE {
        for x in 0..SIZE {
            let sx = (2.0 * (x as f32 + 0.5) / SIZE as f32 - 1.0) * cam.tan_half_fov_y;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32) * cam.tan_half_fov_y;
            let dir = (cam.forward + cam.right * sx + cam.up * sy).normalize();
            let ray = Ray::new(cam.origin, dir);
            if let Some(t) = counted_closest_hit(gpu, &ray, &mut primary) {
                let z = 2.0 * rnd() - 1.0;
                let phi = std::f32::consts::TAU * rnd();
                let r = (1.0 - z * z).max(0.0).sqrt();
                let d = Vec3::new(r * phi.cos(), z, r * phi.sin());
                // Start just off the surface, on the camera's side.
                let d = if d.dot(dir) > 0.0 { -d } else { d };
                let origin = ray.at(t) - dir * 1e-2;
                counted_closest_hit(gpu, &Ray::new(origin, d), &mut bounce);
                bounces += 1;
            }
        }
    }
    (primary, bounce, bounces)
}

/// Leaf-depth histogram (index = depth) and the object ids of the deepest leaf.
fn leaf_depths(gpu: &SceneGpu) -> (Vec<usize>, Vec<u32>) {
    let mut hist = Vec::new();
    let mut deepest = (0usize, 0u32);
    let mut stack = vec![(0u32, 0usize)];
    while let Some((i, d)) = stack.pop() {
        let n = gpu.nodes[i as usize];
        if n.info.x == 0 {
            stack.push((n.info.y, d + 1));
            stack.push((n.info.y + 1, d + 1));
        } else {
            if hist.len() <= d {
                hist.resize(d + 1, 0);
            }
            hist[d] += 1;
            if d >= deepest.0 {
                deepest = (d, i);
            }
        }
    }
    let leaf = gpu.nodes[deepest.1 as usize];
    let mut objects: Vec<u32> = (leaf.info.y..leaf.info.y + leaf.info.x)
        .map(|t| gpu.attrs[t as usize].ids.x)
        .collect();
    objects.dedup();
    (hist, objects)
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// One prepared scene: buffers, parameters and the frame buffers.
struct Bench {
    name: &'static str,
    gpu: SceneGpu,
    params: TraceParams,
    /// Frames per timed sample, per thread configuration.
    reps: Vec<usize>,
    /// Per thread configuration: rays/s and paths/s of each round.
    rays_per_s: Vec<Vec<f64>>,
    paths_per_s: Vec<Vec<f64>>,
    /// Rays per frame (deterministic: fixed seeds).
    rays_per_frame: u64,
}

fn main() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let thread_counts: Vec<usize> = if cores > 1 { vec![1, cores] } else { vec![1] };
    let pools: Vec<rayon::ThreadPool> = thread_counts
        .iter()
        .map(|&t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("thread pool")
        })
        .collect();

    // Scenes.
    let t = Instant::now();
    let big = big_scene();
    let gen_s = t.elapsed().as_secs_f64();
    let big_tris = big.triangles.len();
    assert!(
        big_tris >= MIN_TRIANGLES,
        "big scene has only {big_tris} triangles"
    );
    let cornell = cornell_box();

    // (a) Build times of the big scene, median of BUILDS.
    let vertices: Vec<[Vec3; 3]> = big.triangles.iter().map(|t| t.vertices).collect();
    let mut bvh_s = Vec::new();
    let mut bvh_stats = (0, 0);
    for _ in 0..BUILDS {
        let t = Instant::now();
        let bvh = build_bvh(&vertices).expect("bvh");
        bvh_s.push(t.elapsed().as_secs_f64());
        bvh_stats = (bvh.nodes.len(), bvh.depth);
    }
    let mut scene_s = Vec::new();
    let mut big_gpu = None;
    for _ in 0..BUILDS {
        let t = Instant::now();
        let gpu = SceneGpu::build(&big).expect("big scene");
        scene_s.push(t.elapsed().as_secs_f64());
        big_gpu = Some(gpu);
    }
    let bvh_ms = median(&mut bvh_s) * 1e3;
    let scene_ms = median(&mut scene_s) * 1e3;
    let big_gpu = big_gpu.expect("built");
    let leaves = big_gpu.nodes.iter().filter(|n| n.info.x > 0).count();
    let mean_leaf = big_tris as f64 / leaves as f64;

    // (b) Render throughput, interleaved rounds.
    let settings = TraceSettings::new(SIZE, SIZE);
    let seeds = white_seeds(SIZE, SIZE, 1);
    let pixels = (SIZE * SIZE) as usize;
    let mut color = vec![Vec4::ZERO; pixels];
    let mut benches: Vec<Bench> = [("cornell", &cornell), ("big", &big)]
        .into_iter()
        .map(|(name, scene)| {
            let gpu = if name == "big" {
                big_gpu.clone()
            } else {
                SceneGpu::build(scene).expect("scene")
            };
            let params = gpu.trace_params(&settings, 0).expect("params");
            Bench {
                name,
                gpu,
                params,
                reps: Vec::new(),
                rays_per_s: vec![Vec::new(); thread_counts.len()],
                paths_per_s: vec![Vec::new(); thread_counts.len()],
                rays_per_frame: 0,
            }
        })
        .collect();
    // Warm-up: one frame each, which also sizes the samples.
    for b in &mut benches {
        for pool in &pools {
            let t = Instant::now();
            let rays = pool.install(|| render_frame(&b.gpu, &b.params, &seeds, &mut color).expect("render"));
            let frame = t.elapsed();
            b.rays_per_frame = rays;
            b.reps
                .push((MIN_SAMPLE.as_secs_f64() / frame.as_secs_f64()).ceil().max(1.0) as usize);
        }
    }
    for _ in 0..ROUNDS {
        for (k, pool) in pools.iter().enumerate() {
            for b in &mut benches {
                let reps = b.reps[k];
                let t = Instant::now();
                let mut rays = 0u64;
                for _ in 0..reps {
                    rays +=
                        pool.install(|| render_frame(&b.gpu, &b.params, &seeds, &mut color).expect("render"));
                }
                let secs = t.elapsed().as_secs_f64();
                b.rays_per_s[k].push(rays as f64 / secs);
                b.paths_per_s[k].push((reps * pixels) as f64 / secs);
            }
        }
    }

    // Summary.
    println!();
    println!("=== scale bench (gpu-tracer/benches/scale.rs) ===");
    println!("machine: {} ({} threads available)", cpu_model(), cores);
    println!(
        "big scene: {big_tris} triangles (Cornell walls + light, {0}x{0}-cell terrain, 43 spheres of {1} \
         triangles); generated in {2:.0} ms",
        terrain_cells(),
        SPHERE_SEGMENTS * (2 * SPHERE_RINGS - 2),
        gen_s * 1e3
    );
    println!(
        "BVH build (build_bvh, median of {BUILDS}): {bvh_ms:.0} ms; whole SceneGpu::build: {scene_ms:.0} ms \
         [goal <= 1000 ms for 200k triangles, here {:.0} ms per 200k: {}]",
        bvh_ms * 2e5 / big_tris as f64,
        if bvh_ms * 2e5 / big_tris as f64 <= 1000.0 {
            "met"
        } else {
            "MISSED"
        }
    );
    println!(
        "BVH: {} nodes, {leaves} leaves ({mean_leaf:.2} triangles/leaf), depth {} (cornell: {} nodes, depth {})",
        bvh_stats.0,
        bvh_stats.1,
        benches[0].gpu.nodes.len(),
        benches[0].gpu.bvh_depth
    );
    println!(
        "render: {SIZE}x{SIZE}, 1 spp, max depth 8, fixed white seeds; median of {ROUNDS} interleaved rounds"
    );
    for b in &benches {
        println!(
            "  {:8} rays/frame {} ({:.2} rays/path)",
            b.name,
            b.rays_per_frame,
            b.rays_per_frame as f64 / pixels as f64
        );
    }
    println!("traversal work per ray (host replica of the kernels' traversal, deterministic):");
    for b in &benches {
        let (p, q, n) = traversal_work(&b.gpu);
        let rays = (SIZE * SIZE) as f64;
        println!(
            "  {:8} camera rays: {:.1} nodes, {:.1} box tests, {:.1} triangle tests; bounce rays ({n}): {:.1} \
             nodes, {:.1} box tests, {:.1} triangle tests",
            b.name,
            p.nodes as f64 / rays,
            p.boxes as f64 / rays,
            p.triangles as f64 / rays,
            q.nodes as f64 / n as f64,
            q.boxes as f64 / n as f64,
            q.triangles as f64 / n as f64
        );
    }
    let (hist, objects) = leaf_depths(&benches[1].gpu);
    println!(
        "big scene leaf depths (depth: leaves): {:?}",
        hist.iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .collect::<Vec<_>>()
    );
    println!("deepest leaf's objects: {objects:?}");
    // Ratios per round (the two scenes' samples are adjacent in time, so
    // load from other processes mostly cancels), then the median.
    let mut ratios = Vec::new();
    for k in 0..thread_counts.len() {
        let per_round = |v: &dyn Fn(&Bench) -> &Vec<f64>| -> Vec<f64> {
            v(&benches[0])
                .iter()
                .zip(v(&benches[1]))
                .map(|(c, b)| c / b)
                .collect()
        };
        let mut rays = per_round(&|b: &Bench| &b.rays_per_s[k]);
        let mut paths = per_round(&|b: &Bench| &b.paths_per_s[k]);
        let (lo, hi) = rays
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &r| (l.min(r), h.max(r)));
        ratios.push((median(&mut rays), median(&mut paths), lo, hi));
    }
    for (k, &threads) in thread_counts.iter().enumerate() {
        for b in &mut benches {
            let rays = median(&mut b.rays_per_s[k]);
            let paths = median(&mut b.paths_per_s[k]);
            println!(
                "  {threads} thread(s) {:8} {:>12.0} rays/s {:>10.0} paths/s ({} frames/sample)",
                b.name, rays, paths, b.reps[k]
            );
        }
    }
    for (&threads, &(ratio, paths_ratio, lo, hi)) in thread_counts.iter().zip(&ratios) {
        println!(
            "  {threads} thread(s): cornell_rays_per_s / big_rays_per_s = {ratio:.2} (rounds {lo:.2}..{hi:.2}; \
             paths/s ratio {paths_ratio:.2}) [goal <= 4: {}]",
            if ratio <= 4.0 { "met" } else { "MISSED" }
        );
    }
}
