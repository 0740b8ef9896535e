//! The ground's depth in each shadow cascade, kept between frames (issue 26, point 4:
//! static casters cached per cascade). The ground is the one caster that fills a whole
//! cascade, and it does not move: while neither the cascade's view nor the clipmap the
//! ground is drawn with has changed since it was last drawn, its depth is copied back
//! into the cascade instead of drawn again, and only the casters that move (balls,
//! objects, blades) are drawn over it.
//!
//! Why: on llvmpipe the ground cost the window's frame about 10 ms of its shadow pass
//! (2.8 million depth fragments at its settled state, `sward render --size 468x360`),
//! where a copy of a 1024² depth layer is a memory copy. The clipmap is placed around the
//! camera and its vertices slide (the morph) with the eye, so the key holds the eye's
//! exact position: a still camera keeps the cache, a moving one draws the ground each
//! frame as before. The result is exact either way: the same depth is drawn or copied.

use glam::Mat4;

/// What a cascade's ground was drawn with: the cascade's view-projection and the
/// clipmap's own key (`TerrainPass::shadow_key`: its uniforms without the camera's
/// projection, and the eye).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundKey {
    view_proj: [[f32; 4]; 4],
    clipmap: u64,
}

impl GroundKey {
    /// The key of a cascade seen with `view_proj` over the clipmap keyed `clipmap`.
    pub fn new(view_proj: Mat4, clipmap: u64) -> Self {
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            clipmap,
        }
    }
}

/// How a cascade's ground gets into its layer this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroundStep {
    /// No ground in the maps (it casts no shadow under this sun): every caster drawn in
    /// one pass, as before.
    None,
    /// Drawn into the layer, then copied into the cache.
    Draw,
    /// Copied from the cache.
    Copy,
}

/// The cached ground depth: one layer per cascade, the shadow map's size.
pub struct GroundCache {
    texture: Option<wgpu::Texture>,
    size: (u32, u32),
    keys: [Option<GroundKey>; 4],
}

impl GroundCache {
    /// An empty cache (its texture is made the first time the ground casts).
    pub fn new() -> Self {
        Self {
            texture: None,
            size: (0, 0),
            keys: [None; 4],
        }
    }

    /// Forgets every layer and frees the texture (shadows off, a new map).
    pub fn clear(&mut self) {
        self.texture = None;
        self.size = (0, 0);
        self.keys = [None; 4];
    }

    /// Decides cascade `k`'s step for a ground keyed `key` (`None`: the ground does not
    /// cast) over a map of `resolution`² texels in `layers` layers, making the texture when
    /// needed, and records the key as drawn when it must be drawn.
    pub fn plan(
        &mut self,
        device: &wgpu::Device,
        (resolution, layers): (u32, u32),
        k: usize,
        key: Option<GroundKey>,
    ) -> GroundStep {
        let Some(key) = key else {
            self.keys[k] = None;
            return GroundStep::None;
        };
        if self.size != (resolution, layers) || self.texture.is_none() {
            self.texture = Some(super::depth_layers(
                device,
                "sward.light.ground_cache",
                (resolution, layers),
                wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
            ));
            self.size = (resolution, layers);
            self.keys = [None; 4];
        }
        if self.keys[k] == Some(key) {
            GroundStep::Copy
        } else {
            self.keys[k] = Some(key);
            GroundStep::Draw
        }
    }

    /// Records the copy of layer `k` between `map` and the cache: into the cache after a
    /// [`GroundStep::Draw`], out of it for a [`GroundStep::Copy`].
    pub fn encode_copy(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        map: &wgpu::Texture,
        k: u32,
        step: GroundStep,
    ) {
        let Some(cache) = &self.texture else {
            return;
        };
        let layer = |texture| wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: k },
            aspect: wgpu::TextureAspect::All,
        };
        let size = wgpu::Extent3d {
            width: self.size.0,
            height: self.size.0,
            depth_or_array_layers: 1,
        };
        match step {
            GroundStep::Draw => encoder.copy_texture_to_texture(layer(map), layer(cache), size),
            GroundStep::Copy => encoder.copy_texture_to_texture(layer(cache), layer(map), size),
            GroundStep::None => {}
        }
    }

    /// Bytes held.
    pub fn gpu_bytes(&self) -> u64 {
        if self.texture.is_none() {
            return 0;
        }
        u64::from(self.size.0) * u64::from(self.size.0) * 4 * u64::from(self.size.1)
    }
}

impl Default for GroundCache {
    fn default() -> Self {
        Self::new()
    }
}
