//! Tests of the primitive tests of continuous detection.
//!
//! * `reference.rs`: the independent exact reference (rational distances between hulls; the
//!   exact first meeting of translating primitives).
//! * `truth.rs`: the public ground truth of three simulation steps.
//! * `adversarial.rs`: motions built so that the answer is known (every degenerate case,
//!   scales near 1e-30 and 1e30, offsets 1e6), against the reference.
//! * `band.rs`: the distance-band tests, against motions with a known distance, the
//!   reference and the ground truth, and their timing (ignored).
//! * `impact.rs`: the impact geometry (weights and normal at the time of impact), checked
//!   exactly on the ground truth and on built motions.
//! * `polygons.rs`: moving polygon pairs and whole scenes against the rational reference.
//! * `bench.rs`: the timing over the ground truth (ignored), and the columns
//!   `scripts/bench-ccd-peers.sh` puts beside Tight-Inclusion's.

mod adversarial;
mod band;
mod bench;
mod impact;
mod polygons;
mod reference;
mod truth;

use super::predicate::Kind;
use super::{Points, Toi};
use reference::{dist2_at, inv_pow2, q, speed_bound, Q};

/// How many of the points are the first primitive's.
fn split(kind: Kind) -> usize {
    match kind {
        Kind::VertexFace => 1,
        Kind::EdgeEdge => 2,
    }
}

/// Checks a time of impact with the reference, as far as it can without the exact earliest
/// time (`known`: a time at which the primitives are known to meet):
///
/// * `AT_START` exactly when they meet at 0 (then `t == 0`);
/// * apart (exact distance > 0) at 0 and just before `t` (`t - 2^-40`) and at `t / 2`: a
///   `t` past a meeting that lasts is caught;
/// * not late: `t <= known`;
/// * not early by more than `2^-20`: the distance at `t` is at most what the primitives can
///   close in `2^-20` (the earliest meeting is within `2^-20` after `t`).
fn check_toi(kind: Kind, pts: &Points, toi: Toi, known: Option<&Q>) {
    let s = split(kind);
    let zero = Q::from_integer(0.into());
    let meets_at_0 = dist2_at(pts, s, &zero) == zero;
    assert_eq!(toi.at_start, meets_at_0, "AT_START {toi:?} {pts:?}");
    assert!((0.0..=1.0).contains(&toi.t), "{toi:?}");
    if toi.at_start {
        assert_eq!(toi.t, 0.0);
        return;
    }
    let t = q(toi.t);
    if let Some(k) = known {
        assert!(t <= *k, "late: {toi:?}, they meet at {k} {pts:?}");
    }
    for before in [&t - inv_pow2(40), &t / Q::from_integer(2.into())] {
        if before > zero {
            assert!(
                dist2_at(pts, s, &before) > zero,
                "they meet at {before} before {toi:?} {pts:?}"
            );
        }
    }
    let reach = speed_bound(pts, s) * inv_pow2(20);
    assert!(
        dist2_at(pts, s, &t) <= &reach * &reach,
        "early: {toi:?} is more than 2^-20 before any meeting {pts:?}"
    );
}
