//! The AGC arrow pass against its CPU twin: the same view-projection matrix, applied on the
//! CPU to the mesh [`ArrowMesh::build`] made, predicts where the GPU draws the arrow and in
//! what colour (the shader's Lambert + ambient, computed here from the face normal).

mod common;

use glam::{Mat4, Vec3, Vec4};
use sward::field::HeightField;
use sward::render::arrows::{
    strength_color, ArrowMesh, ArrowPass, AMBIENT, ARROW_LIFT, HEAD_FRACTION, HEAD_MAX_LENGTH,
    SHAFT_WIDTH,
};
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::scene::{Guide, GuidePoint};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;
/// Largest difference per channel (0..255) between the GPU pixel and the CPU prediction:
/// the prediction is exact up to rasterisation (the pixel lies well inside one face) and
/// the 8-bit sRGB encoding (±1), so 6 leaves room without letting a wrong shade through
/// (the ambient-only shade would be off by about 90).
const TOLERANCE: i32 = 6;

fn point(position: (f32, f32), parent: Option<usize>) -> GuidePoint {
    GuidePoint {
        position,
        parent,
        strength: None,
        radius: None,
    }
}

/// Guide 0: one strong arrow along x, all of it in view. Guide 1: long arrows outside the
/// view that make the mesh outgrow the pass's initial buffers.
fn guides() -> Vec<Guide> {
    vec![
        Guide {
            started: 0.0,
            strength: 20.0,
            radius: 1.0,
            points: vec![point((-2.0, 0.0), None), point((2.0, 0.0), Some(0))],
        },
        Guide {
            started: 0.0,
            strength: 5.0,
            radius: 1.0,
            points: vec![
                point((-15.0, 14.0), None),
                point((15.0, 14.0), Some(0)),
                point((-15.0, 15.0), Some(1)),
                point((15.0, 15.8), Some(2)),
            ],
        },
    ]
}

fn camera() -> CameraView {
    CameraView {
        eye: Vec3::new(0.0, 6.5, 2.0),
        target: Vec3::new(0.0, ARROW_LIFT, 0.0),
        fov_y: 35.0,
        near: 0.1,
        far: 100.0,
    }
}

fn sun() -> Vec3 {
    Vec3::new(0.3, 0.9, 0.3).normalize()
}

/// Clip space of a world point.
fn clip(view_proj: Mat4, p: Vec3) -> Vec4 {
    view_proj * p.extend(1.0)
}

/// The pixel (column, row) a world point falls in, with wgpu's conventions (NDC y up,
/// row 0 at the top).
fn pixel(view_proj: Mat4, p: Vec3) -> (u32, u32) {
    let c = clip(view_proj, p);
    assert!(c.w > 0.0, "{p} is behind the camera");
    let ndc = c.truncate() / c.w;
    let x = (ndc.x + 1.0) * 0.5 * WIDTH as f32;
    let y = (1.0 - ndc.y) * 0.5 * HEIGHT as f32;
    assert!(
        x >= 0.0 && y >= 0.0,
        "{p} projects left of or above the image"
    );
    (x.floor() as u32, y.floor() as u32)
}

fn srgb(linear: f32) -> i32 {
    let l = linear.clamp(0.0, 1.0);
    let s = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as i32
}

/// Clears colour to black and depth to `depth`, then runs the arrow pass; returns the image.
fn render(gpu: &sward::gpu::Gpu, pass: &ArrowPass, depth: f32) -> image::RgbaImage {
    let target = Target::new(gpu, WIDTH, HEIGHT).expect("target");
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.test.arrows"),
        });
    {
        let _clear = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.test.clear"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(depth),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    }
    pass.encode(
        &mut encoder,
        &target.color_view,
        &target.depth_view,
        sward::gpu::queries::PassQueries::NONE,
    );
    gpu.queue.submit([encoder.finish()]);
    target.read_image(gpu).expect("read back")
}

fn is_black(p: &image::Rgba<u8>) -> bool {
    p.0[..3] == [0, 0, 0]
}

#[test]
fn the_gpu_draws_the_arrow_where_the_cpu_projects_it() {
    let gpu = common::gpu();
    let terrain = HeightField::flat(32.0, 9);
    let guides = guides();
    let mesh = ArrowMesh::build(&guides, &terrain, None, None);
    assert!(
        mesh.vertices.len() > 1024,
        "the mesh must outgrow the first buffers"
    );
    let view_proj = camera().view_proj(WIDTH as f32 / HEIGHT as f32);
    let mut pass = ArrowPass::new(&gpu, COLOR_FORMAT, 1);

    // An empty mesh draws nothing.
    pass.prepare(&gpu, &ArrowMesh::default(), view_proj, sun());
    let empty = render(&gpu, &pass, 1.0);
    assert!(empty.pixels().all(is_black));

    pass.prepare(&gpu, &mesh, view_proj, sun());
    let image = render(&gpu, &pass, 1.0);

    // The middle of the shaft's top face (flat terrain: the shaft runs at ARROW_LIFT).
    let head = (HEAD_FRACTION * 4.0).min(HEAD_MAX_LENGTH);
    let mid_x = -2.0 + 0.5 * (4.0 - head);
    let top = Vec3::new(mid_x, ARROW_LIFT + 0.5 * SHAFT_WIDTH, 0.0);
    let (px, py) = pixel(view_proj, top);
    // The top face's normal is +y: the shader's shade, computed here.
    let shade = AMBIENT + (1.0 - AMBIENT) * Vec3::Y.dot(sun()).max(0.0);
    let color = strength_color(20.0);
    let expected = [0, 1, 2].map(|i| srgb(color[i] * shade));
    let got = image.get_pixel(px, py).0;
    for i in 0..3 {
        assert!(
            (got[i] as i32 - expected[i]).abs() <= TOLERANCE,
            "pixel ({px}, {py}) is {got:?}, expected {expected:?} ± {TOLERANCE}"
        );
    }
    assert_eq!(
        expected,
        [srgb(shade), srgb(shade), 0],
        "a strong arrow is yellow"
    );

    // Every lit pixel lies inside the projected bounds of guide 0's vertices, one pixel of
    // margin for rasterisation. Guide 1 (z ≥ 14) is outside the view: checked here first.
    let (near, far): (Vec<Vec3>, Vec<Vec3>) = mesh
        .vertices
        .iter()
        .map(|v| Vec3::from(v.position))
        .partition(|p| p.z < 5.0);
    for &p in &far {
        let c = clip(view_proj, p);
        assert!(
            c.w <= 0.0 || c.x.abs() > c.w || c.y.abs() > c.w,
            "{p} is in view"
        );
    }
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0, 0));
    for &p in &near {
        let (x, y) = pixel(view_proj, p);
        assert!(x < WIDTH && y < HEIGHT, "{p} is out of the image");
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let mut lit = 0;
    for (x, y, p) in image.enumerate_pixels() {
        if !is_black(p) {
            lit += 1;
            assert!(
                x + 1 >= lo.0 && x <= hi.0 + 1 && y + 1 >= lo.1 && y <= hi.1 + 1,
                "pixel ({x}, {y}) = {p:?} is lit outside {lo:?}..{hi:?}"
            );
        }
    }
    // A pixel far from every arrow stays black.
    assert!(
        lo.0 > 4 && lo.1 > 4 && hi.0 + 4 < WIDTH && hi.1 + 4 < HEIGHT,
        "{lo:?}..{hi:?}"
    );
    assert!(is_black(image.get_pixel(2, 2)));
    assert!(is_black(image.get_pixel(WIDTH - 3, HEIGHT - 3)));
    assert!(lit > 100, "only {lit} pixels drawn");

    // The depth buffer already holds something nearer than every vertex: all hidden.
    let nearest = near
        .iter()
        .map(|&p| clip(view_proj, p))
        .map(|c| c.z / c.w)
        .fold(f32::MAX, f32::min);
    assert!(nearest > 0.0 && nearest < 1.0, "{nearest}");
    let hidden = render(&gpu, &pass, nearest * 0.999);
    assert!(hidden.pixels().all(is_black), "the arrow shows through");
}
