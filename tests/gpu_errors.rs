//! A wgpu error outside an error scope (wgpu's default handler panics) becomes a clear
//! `Error` from `Gpu::check_errors`, which the commands call after building and after each
//! frame: an invalid resource or pipeline ends the run with a message, not a backtrace.

mod common;

use sward::Error;

#[test]
fn an_invalid_buffer_is_an_error_not_a_panic() {
    let gpu = common::gpu();
    gpu.check_errors().expect("a fresh device has no error");
    // MAP_READ may only be combined with COPY_DST: a validation error.
    let _buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.test.invalid_buffer"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let e = gpu
        .check_errors()
        .expect_err("the invalid buffer is reported");
    let text = e.to_string();
    println!("{text}");
    assert!(matches!(e, Error::Gpu(_)), "{e:?}");
    assert!(text.starts_with("GPU error: "), "{text}");
    assert!(text.contains(&gpu.info.name), "{text}");
    assert!(text.contains("sward.test.invalid_buffer"), "{text}");
    // The device stays marked: a later check fails too.
    assert!(gpu.check_errors().is_err());
}

#[test]
fn an_invalid_pipeline_is_an_error_not_a_panic() {
    let gpu = common::gpu();
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sward.test.shader"),
            source: wgpu::ShaderSource::Wgsl(
                "@group(0) @binding(0) var<storage, read_write> x: array<u32>;\n\
                 @compute @workgroup_size(64) fn main() { x[0] = 1u; }"
                    .into(),
            ),
        });
    gpu.check_errors().expect("the shader is valid");
    // An entry point that does not exist.
    let _pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.test.invalid_pipeline"),
            layout: None,
            module: &module,
            entry_point: Some("missing"),
            compilation_options: Default::default(),
            cache: None,
        });
    let text = gpu
        .check_errors()
        .expect_err("the invalid pipeline is reported")
        .to_string();
    println!("{text}");
    assert!(text.contains("sward.test.invalid_pipeline"), "{text}");
}

#[test]
fn a_sound_renderer_and_frame_leave_no_error() {
    let gpu = common::gpu();
    let session =
        sward::session::Session::new(common::still_scene(), Some(256), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, 2, 1.0 / 30.0);
    gpu.check_errors()
        .expect("no error after building and stepping");
    assert_eq!(r.blades_reset_nonfinite(&gpu).expect("count"), 0);
}
