//! The flagship study: the eversion growing robot of Vartholomeos et al. against the paper's
//! Tables III and VI and its Fig. 6.
//!
//! Everything the libraries know of measured data is generic (an experiment file names the
//! columns); this crate is where the robot's own columns (`P_s_kPa`, `v_ac_mm_s`,
//! `v_ct_mm_s`, `v_ge_mm_s`) have a meaning: the paper's designs, its tables side by side
//! with the models' predictions, the events of its Fig. 6, and the report of
//! `bondgraph reproduce`. It uses the libraries like any user would.
//!
//! - [`columns`]: the robot's measurement columns, read from rows of its experiment;
//! - [`designs`]: the paper's experimental designs, for synthetic data;
//! - [`reproduce`]: the main job, and [`report`], its report;
//! - [`main_job`]: the files `bondgraph reproduce` builds in, `discover` on Table III, and
//!   the command's JSON document.

pub mod columns;
pub mod designs;
pub mod main_job;
pub mod report;
pub mod reproduce;
