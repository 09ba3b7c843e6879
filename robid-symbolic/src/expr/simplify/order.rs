//! Canonical order of commutative operands: by node id, numbers first.
//!
//! Ids are assigned in construction order, which is deterministic, so the
//! order (and every temporary numbered from it later) is reproducible.

use crate::expr::Id;

/// Sorts operands into canonical order.
pub(crate) fn sort(operands: &mut [Id]) {
    operands.sort_unstable();
}
