//! sward's sun shadows in a host's own shader (`sward::embed`'s receiver hook): the parts
//! of `light.wgsl` between its `sward:receiver` markers — the light's uniforms and
//! `sun_visibility_from`, the lookup sward's own passes run — with their names prefixed
//! `sward_` so they do not meet the host's, and the light's three bindings at the host's
//! group. The host binds `LightPass::group` there with `light::layout`.

/// The names the receiver's code declares, and what the host sees them as.
const RENAMES: [(&str, &str); 5] = [
    ("LightUniforms", "SwardLightUniforms"),
    ("light", "sward_light"),
    ("shadow_map", "sward_shadow_map"),
    ("shadow_sampler", "sward_shadow_sampler"),
    ("sun_visibility_from", "sward_sun_visibility"),
];

/// WGSL for a host's shader: `SwardLightUniforms`, the bindings `sward_light`,
/// `sward_shadow_map` and `sward_shadow_sampler` at `@group(group)`, and
/// `fn sward_sun_visibility(world: vec3<f32>, camera: vec3<f32>, sun_dir: vec3<f32>) -> f32`
/// (1 lit, 0 in the sun's shadow).
pub fn receiver_wgsl(group: u32) -> String {
    let source = crate::shaders::source("light.wgsl");
    let mut parts = String::new();
    let mut inside = false;
    for line in source.lines() {
        match line.trim() {
            "// sward:receiver begin" => inside = true,
            "// sward:receiver end" => inside = false,
            _ if inside => {
                parts.push_str(line);
                parts.push('\n');
            }
            _ => {}
        }
    }
    let mut out = format!(
        "// sward's sun shadows (sward::embed::ShadowReceiver), generated from light.wgsl.\n\
         @group({group}) @binding(0) var<uniform> sward_light: SwardLightUniforms;\n\
         @group({group}) @binding(1) var sward_shadow_map: texture_depth_2d_array;\n\
         @group({group}) @binding(2) var sward_shadow_sampler: sampler_comparison;\n"
    );
    out.push_str(&rename(&parts));
    out
}

/// `code` with every identifier of [`RENAMES`] renamed, except a field of the same name
/// (read after a `.`, `light.shadow_map`, or declared before a `:`) and in comments.
fn rename(code: &str) -> String {
    let mut out = String::with_capacity(code.len() + 256);
    for line in code.lines() {
        let (text, comment) = match line.find("//") {
            Some(at) => line.split_at(at),
            None => (line, ""),
        };
        let chars: Vec<char> = text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            if c.is_ascii_alphabetic() || c == '_' {
                let start = i;
                while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                let word: String = chars[start..i].iter().collect();
                // A field: read (`light.shadow_map`) or declared (`shadow_map: vec4<f32>`).
                let read = start > 0 && chars[start - 1] == '.';
                let next = chars[i..].iter().find(|c| !c.is_whitespace());
                let declared = next == Some(&':') && chars.get(i + 1) != Some(&':');
                let field = read || declared;
                match RENAMES.iter().find(|(from, _)| *from == word) {
                    Some((_, to)) if !field => out.push_str(to),
                    _ => out.push_str(&word),
                }
            } else {
                out.push(c);
                i += 1;
            }
        }
        out.push_str(comment);
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_prefixed_but_fields_and_comments_are_not() {
        let code = "let a = light.shadow_map.x; // light\nlet b = textureSampleCompareLevel(shadow_map, shadow_sampler, uv, k, z);\n    shadow_map: vec4<f32>,\n";
        assert_eq!(
            rename(code),
            "let a = sward_light.shadow_map.x; // light\n\
             let b = textureSampleCompareLevel(sward_shadow_map, sward_shadow_sampler, uv, k, z);\n    \
             shadow_map: vec4<f32>,\n"
        );
    }

    #[test]
    fn the_receiver_has_the_uniforms_and_the_lookup_at_the_hosts_group() {
        let w = receiver_wgsl(3);
        assert!(w.contains("@group(3) @binding(0) var<uniform> sward_light: SwardLightUniforms;"));
        assert!(w.contains("struct SwardLightUniforms {"));
        assert!(w.contains("fn sward_sun_visibility(world: vec3<f32>, camera: vec3<f32>"));
        // Nothing of sward's own frame or names is left for the host to provide.
        let code: String = w
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n")
            .replace("SwardLightUniforms {", "");
        for name in ["frame.", " light.", "(light.", "LightUniforms {"] {
            assert!(!code.contains(name), "{name} left in the receiver:\n{w}");
        }
    }
}
