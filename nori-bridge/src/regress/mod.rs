//! `make regress SIM=cpp` without a JVM: the report half (scripts/regress-cpp.sh
//! runs the simulator, the C++ golden check and `compare`, then `regress-report`).

pub mod report;
