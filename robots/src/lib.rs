//! Reference robots.
