//! `nori-bridge sweep-report`: the precision sweep's per-point results in
//! (`input`), derived metrics (`runs`, `metrics`, `summary`, `pareto`), the
//! report out as JSON (`report`), markdown (`md`, `md_hard`) and plots
//! (`plot`, `chart`).

pub mod chart;
pub mod input;
pub mod md;
pub mod md_hard;
pub mod metrics;
pub mod pareto;
pub mod plot;
pub mod report;
pub mod runs;
pub mod summary;
