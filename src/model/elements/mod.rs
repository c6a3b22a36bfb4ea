//! Element matrices. One module per element type:
//!
//! - [`frame`]: the local axes of a beam (orientation rule of the deck spec)
//!   and the rotation of 12×12 element matrices to global axes;
//! - [`beam`]: the 12×12 local stiffness and consistent mass of a 3D frame
//!   beam, Euler–Bernoulli or Timoshenko (Przemieniecki);
//! - [`lumped`]: nodal masses/rotary inertias and springs.
//!
//! The plane (x–z) frame element is the 3D element restricted to the global
//! DOFs x, z, ry of its two nodes: for a beam in the x–z plane with local y
//! along ±global y those DOFs decouple exactly from y, rx, rz, so plane and
//! space analyses agree by construction and share the sign convention
//! θy = −dw/dx (right-hand rotation about +y turns +x towards −z).

pub mod beam;
pub mod frame;
pub mod lumped;
