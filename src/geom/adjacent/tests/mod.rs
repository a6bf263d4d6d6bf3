//! The predicate against an independent exact oracle, on adversarial cases.
//!
//! The oracle ([`oracle::meets`]) shares nothing with the predicate but the definitions:
//! it *constructs* `t ∩ u` in exact rationals and measures it.
//!
//! * `oracle.rs`: the oracle, in `i128` (overflows flagged) or `BigInt`.
//! * `support.rs`: a case (two polygons) and the tally of a family of cases against the
//!   oracle.
//! * `families.rs`: random families (grids, folds, pushed vertices, pinched fans, sliver
//!   fans) against the oracle.
//! * `cases.rs`: named cases, sharing by index, a real mesh, and the cloth timing
//!   (ignored).

mod cases;
mod families;
mod oracle;
mod support;
