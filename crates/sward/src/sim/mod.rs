//! Simulation: the blade update on the GPU, its CPU twin, collider motion and the Pod
//! layouts shared with the shaders.

pub mod agc;
pub mod bvh;
pub mod carry;
pub mod carry_pass;
pub mod colliders;
pub mod cwd;
pub mod fluid;
pub mod health;
pub mod layout;
pub mod params;
pub mod propagation;
pub mod propagation_pass;
pub mod reference;
pub mod update;
pub mod verlet;
pub mod wind_layout;
