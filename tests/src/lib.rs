//! End-to-end tests of the command-line tools; see `tests/`.
