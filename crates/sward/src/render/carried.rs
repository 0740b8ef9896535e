//! The renderer's part in carrying grass on moving objects (`sim::carry`): each step it
//! works out where every carried object is (M(t) and the step's motion), hands that to the
//! carry pass and writes the objects' moved patch boxes, then records the pass before the
//! patch pass, so the culling, the broad phase and the update all see the blades where the
//! object is now.

use glam::Mat4;

use crate::error::Result;
use crate::field::HeightField;
use crate::gpu::Gpu;
use crate::scene::Scene;
use crate::sim::carry::{self, Carried};
use crate::sim::carry_pass::CarryPass;
use crate::sim::layout::PatchBox;
use crate::sim::update::BladeBuffers;

pub(super) struct CarriedGrass {
    pass: CarryPass,
    /// The carried objects' patches at rest (the blades' rest copies live on the GPU).
    carried: Carried,
    /// Last step's M of each carried object (identity at the start: the blades were grown
    /// at rest).
    previous: Vec<Mat4>,
}

impl CarriedGrass {
    /// `None` when nothing with grass moves; `carried` indexes the GPU's blades.
    pub(super) fn new(
        gpu: &Gpu,
        buffers: &BladeBuffers,
        carried: &Carried,
    ) -> Result<Option<Self>> {
        if carried.is_empty() {
            return Ok(None);
        }
        let pass = CarryPass::new(gpu, buffers, &carried.blades, carried.objects.len())?;
        let carried = Carried {
            blades: Vec::new(),
            objects: carried.objects.clone(),
        };
        let previous = vec![Mat4::IDENTITY; carried.objects.len()];
        Ok(Some(Self {
            pass,
            carried,
            previous,
        }))
    }

    /// Moves the carried objects to `time`: the pass's motions and the patch boxes.
    pub(super) fn advance(
        &mut self,
        gpu: &Gpu,
        buffers: &BladeBuffers,
        scene: &Scene,
        terrain: &HeightField,
        time: f32,
    ) {
        let (models, motions) = carry::step(
            &self.carried,
            &scene.objects,
            terrain,
            time,
            &mut self.previous,
        );
        self.pass.prepare(&gpu.queue, &motions);
        for (first, boxes) in carry::moved_boxes(&self.carried, &models) {
            gpu.queue.write_buffer(
                &buffers.patches,
                (first * std::mem::size_of::<PatchBox>()) as u64,
                bytemuck::cast_slice(&boxes),
            );
        }
    }

    pub(super) fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        self.pass.encode(encoder);
    }
}
