//! Umlauf–Prautzsch triangular G^k splines [UP].

pub mod box_spline;
pub mod jets;
