//! The limits a scene is checked against, kept with the scene (the bottom layer) so that
//! its validation does not reach up into the layers that use them: the simulation's
//! collider and propagation bounds, the renderer's sample counts and the field's species
//! and flower kinds. Those layers re-export them where they are used.

/// Upper bound on sphere colliders uploaded per frame: enough for the 10,000 spheres of the
/// hierarchy's cost table (issue 14); a flat list of that many is what the hierarchy beats.
pub const MAX_SPHERES: usize = 16384;

/// Most generations of grass-to-grass propagation per step (each is one dispatch).
pub const MAX_GENERATIONS: u32 = 16;

/// The sample counts a scene may ask for (`render.msaa`).
pub const SAMPLE_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// Species a field mixes at most.
pub const MAX_SPECIES: usize = 8;

/// Kinds of flower a field has at most.
pub const MAX_FLOWER_KINDS: usize = 4;
