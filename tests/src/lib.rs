//! Cross-crate integration tests live in `tests/tests/`: the whole pipeline, from a plan
//! or a learning run to image bytes, to the executor ticking a world. This library is
//! empty on purpose.
