//! The hard-case suite: scenes and rays built in code with exact integer
//! expectations (`cases` writes them, `spheres`, `planes`, `thin` build
//! them on `mesh`, `exact` decides), and `score` for a hits file against
//! a case's expect.csv.

pub mod cases;
pub mod exact;
pub mod mesh;
pub mod planes;
pub mod score;
pub mod spheres;
pub mod thin;
