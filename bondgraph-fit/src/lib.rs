//! Measured data against bond-graph models.
