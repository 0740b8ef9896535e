//! WGSL sources: one entry file per pass, with shared structs pulled in by a small include
//! step (`//!include FILE` on a line of its own). Sources are embedded at build time so the
//! binary runs from any directory.

/// Every WGSL file, by name, as shipped in `shaders/`.
const FILES: &[(&str, &str)] = &[
    ("common.wgsl", include_str!("../shaders/common.wgsl")),
    ("light.wgsl", include_str!("../shaders/light.wgsl")),
    (
        "blade_shade.wgsl",
        include_str!("../shaders/blade_shade.wgsl"),
    ),
    ("far_grass.wgsl", include_str!("../shaders/far_grass.wgsl")),
    ("canopy.wgsl", include_str!("../shaders/canopy.wgsl")),
    (
        "canopy_probe.wgsl",
        include_str!("../shaders/canopy_probe.wgsl"),
    ),
    (
        "grass_texture.wgsl",
        include_str!("../shaders/grass_texture.wgsl"),
    ),
    (
        "far_grass_probe.wgsl",
        include_str!("../shaders/far_grass_probe.wgsl"),
    ),
    (
        "far_gain_math.wgsl",
        include_str!("../shaders/far_gain_math.wgsl"),
    ),
    ("far_sectors.wgsl", include_str!("../shaders/far_sectors.wgsl")),
    (
        "far_sectors_probe.wgsl",
        include_str!("../shaders/far_sectors_probe.wgsl"),
    ),
    (
        "far_gain_common.wgsl",
        include_str!("../shaders/far_gain_common.wgsl"),
    ),
    ("far_gain.wgsl", include_str!("../shaders/far_gain.wgsl")),
    (
        "far_gain_msaa.wgsl",
        include_str!("../shaders/far_gain_msaa.wgsl"),
    ),
    (
        "far_gain_probe.wgsl",
        include_str!("../shaders/far_gain_probe.wgsl"),
    ),
    (
        "contrast_probe.wgsl",
        include_str!("../shaders/contrast_probe.wgsl"),
    ),
    (
        "card_profile.wgsl",
        include_str!("../shaders/card_profile.wgsl"),
    ),
    (
        "card_profile_probe.wgsl",
        include_str!("../shaders/card_profile_probe.wgsl"),
    ),
    ("thinning.wgsl", include_str!("../shaders/thinning.wgsl")),
    (
        "thinning_probe.wgsl",
        include_str!("../shaders/thinning_probe.wgsl"),
    ),
    ("lod_chord.wgsl", include_str!("../shaders/lod_chord.wgsl")),
    (
        "lod_chord_probe.wgsl",
        include_str!("../shaders/lod_chord_probe.wgsl"),
    ),
    (
        "distance_gain_probe.wgsl",
        include_str!("../shaders/distance_gain_probe.wgsl"),
    ),
    (
        "div_small_probe.wgsl",
        include_str!("../shaders/div_small_probe.wgsl"),
    ),
    ("octahedral.wgsl", include_str!("../shaders/octahedral.wgsl")),
    (
        "octahedral_probe.wgsl",
        include_str!("../shaders/octahedral_probe.wgsl"),
    ),
    (
        "grass_texture_probe.wgsl",
        include_str!("../shaders/grass_texture_probe.wgsl"),
    ),
    (
        "trail_probe.wgsl",
        include_str!("../shaders/trail_probe.wgsl"),
    ),
    ("wind.wgsl", include_str!("../shaders/wind.wgsl")),
    ("update.wgsl", include_str!("../shaders/update.wgsl")),
    (
        "update_common.wgsl",
        include_str!("../shaders/update_common.wgsl"),
    ),
    (
        "collide_walk.wgsl",
        include_str!("../shaders/collide_walk.wgsl"),
    ),
    (
        "update_verlet.wgsl",
        include_str!("../shaders/update_verlet.wgsl"),
    ),
    (
        "update_cwd.wgsl",
        include_str!("../shaders/update_cwd.wgsl"),
    ),
    ("cwd.wgsl", include_str!("../shaders/cwd.wgsl")),
    (
        "update_slot.wgsl",
        include_str!("../shaders/update_slot.wgsl"),
    ),
    (
        "thin_order.wgsl",
        include_str!("../shaders/thin_order.wgsl"),
    ),
    ("propagate.wgsl", include_str!("../shaders/propagate.wgsl")),
    ("clumps.wgsl", include_str!("../shaders/clumps.wgsl")),
    (
        "blade_pose.wgsl",
        include_str!("../shaders/blade_pose.wgsl"),
    ),
    ("tile_gen.wgsl", include_str!("../shaders/tile_gen.wgsl")),
    ("trails.wgsl", include_str!("../shaders/trails.wgsl")),
    (
        "wind_sample.wgsl",
        include_str!("../shaders/wind_sample.wgsl"),
    ),
    ("billboard.wgsl", include_str!("../shaders/billboard.wgsl")),
    (
        "billboard_place.wgsl",
        include_str!("../shaders/billboard_place.wgsl"),
    ),
    (
        "billboard_sway.wgsl",
        include_str!("../shaders/billboard_sway.wgsl"),
    ),
    (
        "billboard_probe.wgsl",
        include_str!("../shaders/billboard_probe.wgsl"),
    ),
    (
        "billboard_cull.wgsl",
        include_str!("../shaders/billboard_cull.wgsl"),
    ),
    ("cull.wgsl", include_str!("../shaders/cull.wgsl")),
    ("cull_order.wgsl", include_str!("../shaders/cull_order.wgsl")),
    (
        "workgroup_scan.wgsl",
        include_str!("../shaders/workgroup_scan.wgsl"),
    ),
    (
        "cull_broad_phase.wgsl",
        include_str!("../shaders/cull_broad_phase.wgsl"),
    ),
    ("bvh_node.wgsl", include_str!("../shaders/bvh_node.wgsl")),
    ("carry.wgsl", include_str!("../shaders/carry.wgsl")),
    ("hiz.wgsl", include_str!("../shaders/hiz.wgsl")),
    ("grass.wgsl", include_str!("../shaders/grass.wgsl")),
    ("grass_vis.wgsl", include_str!("../shaders/grass_vis.wgsl")),
    (
        "grass_deferred.wgsl",
        include_str!("../shaders/grass_deferred.wgsl"),
    ),
    (
        "grass_deferred_msaa.wgsl",
        include_str!("../shaders/grass_deferred_msaa.wgsl"),
    ),
    ("terrain.wgsl", include_str!("../shaders/terrain.wgsl")),
    (
        "terrain_height.wgsl",
        include_str!("../shaders/terrain_height.wgsl"),
    ),
    (
        "terrain_probe.wgsl",
        include_str!("../shaders/terrain_probe.wgsl"),
    ),
    ("sky.wgsl", include_str!("../shaders/sky.wgsl")),
    ("spheres.wgsl", include_str!("../shaders/spheres.wgsl")),
    ("mesh.wgsl", include_str!("../shaders/mesh.wgsl")),
    ("overlay.wgsl", include_str!("../shaders/overlay.wgsl")),
    ("arrows.wgsl", include_str!("../shaders/arrows.wgsl")),
    ("upscale.wgsl", include_str!("../shaders/upscale.wgsl")),
    (
        "ui_composite.wgsl",
        include_str!("../shaders/ui_composite.wgsl"),
    ),
    ("tonemap.wgsl", include_str!("../shaders/tonemap.wgsl")),
    ("taa.wgsl", include_str!("../shaders/taa.wgsl")),
    ("taa_prev.wgsl", include_str!("../shaders/taa_prev.wgsl")),
    ("skin.wgsl", include_str!("../shaders/skin.wgsl")),
    (
        "fluid_common.wgsl",
        include_str!("../shaders/fluid_common.wgsl"),
    ),
    (
        "fluid_splat.wgsl",
        include_str!("../shaders/fluid_splat.wgsl"),
    ),
    (
        "fluid_vorticity.wgsl",
        include_str!("../shaders/fluid_vorticity.wgsl"),
    ),
    (
        "fluid_diffuse.wgsl",
        include_str!("../shaders/fluid_diffuse.wgsl"),
    ),
    (
        "fluid_divergence.wgsl",
        include_str!("../shaders/fluid_divergence.wgsl"),
    ),
    (
        "fluid_pressure.wgsl",
        include_str!("../shaders/fluid_pressure.wgsl"),
    ),
    (
        "fluid_gradient.wgsl",
        include_str!("../shaders/fluid_gradient.wgsl"),
    ),
    (
        "fluid_advect.wgsl",
        include_str!("../shaders/fluid_advect.wgsl"),
    ),
    (
        "fluid_scroll.wgsl",
        include_str!("../shaders/fluid_scroll.wgsl"),
    ),
    (
        "fluid_multigrid.wgsl",
        include_str!("../shaders/fluid_multigrid.wgsl"),
    ),
    (
        "fluid_centre.wgsl",
        include_str!("../shaders/fluid_centre.wgsl"),
    ),
];

/// The entry files, one per pass (the others are only included).
pub const ENTRY_FILES: &[&str] = &[
    "propagate.wgsl",
    "update.wgsl",
    "update_verlet.wgsl",
    "update_cwd.wgsl",
    "carry.wgsl",
    "tile_gen.wgsl",
    "billboard.wgsl",
    "billboard_probe.wgsl",
    "billboard_cull.wgsl",
    "cull.wgsl",
    "hiz.wgsl",
    "grass.wgsl",
    "grass_deferred.wgsl",
    "grass_deferred_msaa.wgsl",
    "terrain.wgsl",
    "terrain_probe.wgsl",
    "far_grass_probe.wgsl",
    "far_gain.wgsl",
    "far_gain_msaa.wgsl",
    "far_gain_probe.wgsl",
    "far_sectors_probe.wgsl",
    "contrast_probe.wgsl",
    "card_profile_probe.wgsl",
    "distance_gain_probe.wgsl",
    "thinning_probe.wgsl",
    "lod_chord_probe.wgsl",
    "div_small_probe.wgsl",
    "octahedral_probe.wgsl",
    "grass_texture_probe.wgsl",
    "canopy_probe.wgsl",
    "trail_probe.wgsl",
    "sky.wgsl",
    "spheres.wgsl",
    "mesh.wgsl",
    "overlay.wgsl",
    "arrows.wgsl",
    "upscale.wgsl",
    "ui_composite.wgsl",
    "tonemap.wgsl",
    "taa.wgsl",
    "taa_prev.wgsl",
    "skin.wgsl",
    "fluid_splat.wgsl",
    "fluid_vorticity.wgsl",
    "fluid_diffuse.wgsl",
    "fluid_divergence.wgsl",
    "fluid_pressure.wgsl",
    "fluid_gradient.wgsl",
    "fluid_advect.wgsl",
    "fluid_multigrid.wgsl",
    "fluid_centre.wgsl",
    "fluid_scroll.wgsl",
];

fn raw(name: &str) -> Option<&'static str> {
    FILES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// The full source of an entry file with its includes expanded (each file at most once).
///
/// # Panics
/// If `name` or an included file is not in the embedded list: that is a build defect, not
/// user input.
pub fn source(name: &str) -> String {
    let mut out = String::new();
    let mut seen = Vec::new();
    expand(name, &mut out, &mut seen);
    out
}

fn expand(name: &str, out: &mut String, seen: &mut Vec<String>) {
    if seen.iter().any(|s| s == name) {
        return;
    }
    seen.push(name.to_string());
    let text = raw(name).unwrap_or_else(|| panic!("shader {name} is not embedded"));
    for line in text.lines() {
        if let Some(inc) = line.trim().strip_prefix("//!include ") {
            expand(inc.trim(), out, seen);
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
}

/// Creates the shader module of an entry file.
pub fn module(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&format!("sward.shader.{name}")),
        source: wgpu::ShaderSource::Wgsl(source(name).into()),
    })
}
