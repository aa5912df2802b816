use gpu_tracer::cornell::cornell_box;
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use glam::Vec2;
#[test]
fn probe() {
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let n = 64u32;
    let params = scene.trace_params(&TraceSettings::new(n, n), 0).unwrap();
    for y in 0..n {
        let mut line = String::new();
        for x in 0..n {
            let ray = kernels::camera::primary_ray(&params, x, y, Vec2::splat(0.5));
            let c = match kernels::bvh::closest_hit(&scene.nodes, &scene.triangles, &ray, 0.0, f32::MAX) {
                None => ' ',
                Some(h) => {
                    let t = scene.triangles[h.triangle as usize];
                    let p = ray.origin + ray.dir * h.t;
                    let m = t.v0.w as u32;
                    if m == 1 { 'R' } else if m == 2 { 'G' } else if m == 3 { 'L' } else if p.z >= 559.0 { 'B' } else if p.y <= 0.5 { 'F' } else if p.y >= 548.0 { 'C' } else { 'x' }
                }
            };
            line.push(c);
        }
        println!("{y:2} {line}");
    }
}
#[test]
fn insets_ok() {
    use conformance::render_study::*;
    for size in [32u32, 64, 128, 256] {
        let r = Study::new(StudyConfig::new(size, 1, 1, 2), None, |_, _| {});
        println!("{size}: {:?}", r.map(|s| s.insets.iter().map(|i| (i.x0, i.y0, i.side, i.max_gradient)).collect::<Vec<_>>()));
    }
}
