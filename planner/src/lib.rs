//! Backchaining synthesis of reactive behavior trees (Colledanchise, Almeida, Ögren,
//! ICRA 2019 — seed 000).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod duplo;
pub mod tokens;
