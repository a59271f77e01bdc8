//! The mobile manipulator of seed 000 Fig. 1.
