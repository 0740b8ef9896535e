//! The coverage measurement of a counted frame: how many pixels the grass covers in the
//! finished picture, the denominator of the lit grass's fragments per pixel
//! (`timing::lit_fragments_per_pixel`). The blades of both draws are drawn again, depth
//! only, passing only where their depth is the frame's (`Equal`; the grass's clip position
//! is `@invariant`, so the same blade lands on the same depth), inside the work counter's
//! occlusion query. It writes nothing and runs only in frames the counter counts; the
//! bench counts separate frames from the ones it times.

use super::draw::DrawPass;
use super::grass_spec::GrassSpec;
use super::pipelines::{depth_only_pipeline, DepthOnly};
use crate::gpu::queries::PassQueries;
use crate::sim::layout::CullCounters;

/// The coverage pipeline, made on the first counted frame and again when the sample
/// count or the grass's specialisation changes (the blades must land on the lit draw's
/// depth to the bit, so it is built with the same constants).
#[derive(Default)]
pub struct Coverage {
    pipeline: Option<((u32, GrassSpec), wgpu::RenderPipeline)>,
}

impl Coverage {
    fn pipeline(&mut self, device: &wgpu::Device, draw: &DrawPass) -> &wgpu::RenderPipeline {
        let key = (draw.samples(), draw.grass_spec());
        if self.pipeline.as_ref().is_none_or(|(k, _)| *k != key) {
            let pipeline = build(device, key, draw.grass_layout());
            self.pipeline = Some((key, pipeline));
        }
        &self.pipeline.as_ref().expect("made above").1
    }

    /// Records the measurement over `depth` (the frame's, after every grass draw): the
    /// main draws of `indirect`, and the late ones with `late`. Nothing when the frame is
    /// not counted.
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        draw: &DrawPass,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        (indirect, late): (&wgpu::Buffer, bool),
        q: PassQueries,
    ) {
        let Some(set) = q.coverage_set() else {
            return;
        };
        let pipeline = self.pipeline(device, draw);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.coverage"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: q.render_writes(),
            occlusion_query_set: Some(set),
            multiview_mask: None,
        });
        q.begin(&mut pass);
        pass.begin_occlusion_query(0);
        draw.draw_grass(&mut pass, pipeline, indirect, 0);
        if late {
            let offset = std::mem::offset_of!(CullCounters, late_draws) as u64;
            draw.draw_grass(&mut pass, pipeline, indirect, offset);
        }
        pass.end_occlusion_query();
        q.end(&mut pass);
    }
}

/// The grass's vertex stage, depth tested `Equal` without writing, no fragment stage.
fn build(
    device: &wgpu::Device,
    (samples, spec): (u32, GrassSpec),
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let depth = DepthOnly {
        compare: wgpu::CompareFunction::Equal,
        write: false,
        bias: Default::default(),
        samples,
    };
    let stage = ("grass.wgsl", "vs_main");
    depth_only_pipeline(
        device,
        "sward.coverage",
        stage,
        layout,
        &[],
        &spec.constants(),
        depth,
    )
}
