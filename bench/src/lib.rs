//! Criterion benchmarks of picomis (see benches/).
