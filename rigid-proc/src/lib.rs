//! rigid-proc's physics: rigid bodies with shapes and mass properties,
//! Euler's equations with Euler parameters advanced by RK4, attachment
//! impulses and rigid–rigid contacts with restitution (dissertation §2.1, §2.4,
//! §3.1.1, §3.4). The physics never touches the coupling: `driver.rs`
//! connects it to the participant library, and `main.rs` only calls it.

pub mod bodies;
pub mod checkpoint;
pub mod contact;
pub mod driver;
pub mod motion;
pub mod output;
pub mod rk4;

pub use bodies::Bodies;
pub use motion::Load;
