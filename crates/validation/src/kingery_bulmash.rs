//! Kingery–Bulmash fits for a spherical free-air burst of TNT: the
//! reference the E-FREEAIR validation case (a 1 kg TNT sphere detonating in
//! free air) compares against.
//!
//! # The fits
//!
//! C. N. Kingery and G. Bulmash, *Airblast parameters from TNT spherical air
//! burst and hemispherical surface burst*, Technical Report ARBRL-TR-02555,
//! U.S. Army Ballistic Research Laboratory, Aberdeen Proving Ground, MD
//! (April 1984), fit each blast-wave parameter Y of a sea-level burst as a
//! polynomial in the logarithm of the scaled distance Z = R / W^(1/3):
//!
//! ```text
//! U        = K0 + K1 · log10 Z
//! log10 Y  = C0 + C1 U + C2 U² + … + Cn Uⁿ
//! ```
//!
//! piecewise in Z where one polynomial does not cover the whole range. These
//! are the curves of UFC 3-340-02, *Structures to Resist the Effects of
//! Accidental Explosions* (2008), Figure 2-7, "Positive phase shock wave
//! parameters for a spherical TNT explosion in free air at sea level", and
//! the ones ConWep evaluates for a free-air burst.
//!
//! # Where the coefficients come from
//!
//! The 1984 report itself was not at hand. The coefficients below are the
//! metric-unit set (Z in m/kg^(1/3); pressure in kPa; scaled impulse in
//! kPa·ms/kg^(1/3); scaled times in ms/kg^(1/3)) as transcribed, with their
//! ranges, by S. K. McNeill in the public repository
//! `lightsquared/kingery_bulmash` (files `1_configuration/models/kb_old.py` for the full-precision
//! coefficients and `1_configuration/models/kb_equation_data.csv` for the
//! ranges, in both unit systems). They were checked against two other
//! public transcriptions:
//!
//! - the English-unit set (Z in ft/lb^(1/3); psi; psi·ms/lb^(1/3);
//!   ms/lb^(1/3)) of the ConWep air-blast routines as coded in the AERO-S
//!   finite-element code, file `packages/aeros/Utils.d/Conwep.d/BlastLoading.C`
//!   (the `AirBurst` branches), public repository `anarkh97/sofics`;
//! - the free-air tables of OpenRadioss, file
//!   `common_source/modules/loads/pblast_mod.F90`, labelled "figure 2_7":
//!   256 points on Z_i = 0.05 · 800^(i/255) m/kg^(1/3) in g–cm–µs–Mbar units.
//!
//! The metric and English sets are one fit written in two unit systems: the
//! higher coefficients C1…Cn and the slope K1 are the same numbers, C0
//! differs by log10 of the unit factor of Y and K0 by K1 · log10 2.520809
//! (1 m/kg^(1/3) = 2.520811 ft/lb^(1/3)). These identities hold to 3·10⁻⁶ in
//! the logarithm for every coefficient below, and they arbitrate the few
//! places where transcriptions disagree: the English-unit slope of the third
//! duration segment is 3.1524725364 (the AERO-S copy reads 3.1524725264), the
//! English-unit offset of that segment is −4.39590184126 (the `kb_old.py`
//! copy reads −4.39590134126), C5 of the second duration segment is
//! −0.00106321963576 (`kb_old.py` drops the sign in its metric copy), C2 of
//! the reflected pressure is 0.035119031446 (`kb_old.py` reads 0.35119…).
//! The last coefficient of the reflected pressure is −0.00397126276058 in
//! AERO-S and `kb_old.py` and is what reproduces the OpenRadioss table; a
//! variant −0.00387… that circulates in other calculators misses that table
//! by 1.2 % at Z = 20 m/kg^(1/3). The unit tests evaluate the English-unit
//! set and the OpenRadioss table values independently of this module's
//! coefficients and measure the agreement (≤ 4·10⁻⁶ and ≤ 5·10⁻⁵
//! respectively; see the tests).
//!
//! No public text quoting numbers read off Figure 2-7 for the free-air
//! burst was found to compare with, so the chart itself enters only through
//! these transcriptions of the fits it plots. As an independent check of the
//! physics the tests compare the shock speed implied by the arrival-time fit,
//! 1 / (dt_a/dR), with the Rankine–Hugoniot shock speed of air (γ = 1.4,
//! p₀ = 101.325 kPa, c₀ = 340.29 m/s) at the peak overpressure of the
//! overpressure fit: the two, fitted separately, agree to 2.6 % over
//! Z = 0.5–20 m/kg^(1/3) (within 2.6 % up to Z = 35; the slope of the
//! arrival-time fit drifts to 7 % at the top of its range, Z = 40).
//!
//! # Units at the boundary
//!
//! Everything here takes and returns SI: range in m, charge mass in kg (of
//! TNT), Z in m/kg^(1/3), pressure in Pa, impulse in Pa·s (scaled:
//! Pa·s/kg^(1/3)), times in s (scaled: s/kg^(1/3)). From the metric fits:
//! 1 kPa = 10³ Pa, 1 kPa·ms = 1 Pa·s, 1 ms = 10⁻³ s. Scaled impulses and
//! times become absolute ones on multiplying by W^(1/3) (Hopkinson–Cranz
//! scaling; the fits are for sea-level ambient air, with no altitude
//! correction).
//!
//! # Valid ranges
//!
//! | quantity | fn | Z range, m/kg^(1/3) | segments split at |
//! |---|---|---|---|
//! | incident (side-on) peak overpressure | [`incident_overpressure`] | 0.0531–40 | — |
//! | normally reflected peak pressure | [`reflected_pressure`] | 0.0531–40 | — |
//! | positive-phase incident impulse | [`scaled_incident_impulse`] | 0.0531–40 | 0.792 |
//! | arrival time | [`scaled_arrival_time`] | 0.0531–40 | — |
//! | positive-phase duration | [`scaled_positive_duration`] | 0.147–40 | 0.888, 2.28 |
//!
//! (In English units 0.134–100, 0.37–100 ft/lb^(1/3); splits at 2.0, 2.24
//! and 5.75 ft/lb^(1/3).) All cover the Z = 0.5–20 m/kg^(1/3) that
//! E-FREEAIR needs. Below 0.147 m/kg^(1/3) the source gives no duration fit
//! (the AERO-S ConWep routine holds the duration constant below
//! 0.457 ft/lb^(1/3), 0.181 m/kg^(1/3); that extension is not reproduced).
//! Outside a range the functions return [`KbError::OutOfRange`]; nothing
//! here panics.
//!
//! A segment covers [Z_lo, Z_hi) and the last one also its upper end; at a
//! split the upper segment is used. The published segments do not meet
//! exactly: the impulse steps down 0.40 % at 0.792, the duration steps up
//! 0.92 % at 0.888 and 0.086 % at 2.28 m/kg^(1/3).
//!
//! # Shape
//!
//! Overpressure and reflected pressure fall and arrival time rises
//! monotonically over the whole range. The impulse falls from 0.0531 to a
//! minimum near Z = 0.41, rises to a peak at the 0.792 split and falls
//! monotonically beyond; the duration dips near Z = 0.26 and 1.5. These
//! humps belong to the fits (and to Figure 2-7), not to this code.
//!
//! # Values (W = 1 kg)
//!
//! | Z, m/kg^(1/3) | P_so, kPa | i_s, Pa·s | t_a, ms | t_0, ms | P_r, kPa |
//! |---|---|---|---|---|---|
//! | 0.5 | 3884.8 | 141.29 | 0.15408 | 0.31965 | 30 360 |
//! | 1 | 934.86 | 174.54 | 0.53184 | 1.7949 | 5005.6 |
//! | 2 | 194.67 | 92.122 | 1.9440 | 1.8459 | 645.83 |
//! | 3 | 81.589 | 64.331 | 3.9874 | 2.6846 | 215.50 |
//! | 5 | 31.296 | 40.619 | 8.9953 | 3.3334 | 70.023 |
//! | 10 | 11.091 | 21.131 | 22.722 | 4.1995 | 23.313 |
//! | 20 | 4.4512 | 10.752 | 50.968 | 5.1425 | 9.0327 |

use std::fmt;

/// A blast-wave parameter with a Kingery–Bulmash free-air fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Peak incident (side-on) overpressure.
    IncidentOverpressure,
    /// Peak normally reflected pressure.
    ReflectedPressure,
    /// Positive-phase incident impulse.
    IncidentImpulse,
    /// Arrival time of the shock.
    ArrivalTime,
    /// Duration of the positive phase.
    PositiveDuration,
}

impl Quantity {
    /// Every quantity, in declaration order.
    pub const ALL: [Quantity; 5] = [
        Quantity::IncidentOverpressure,
        Quantity::ReflectedPressure,
        Quantity::IncidentImpulse,
        Quantity::ArrivalTime,
        Quantity::PositiveDuration,
    ];

    /// The published range of Z of this quantity's fit, `(min, max)` in
    /// m/kg^(1/3), both ends included.
    pub fn valid_range(self) -> (f64, f64) {
        let fit = fit(self);
        (fit[0].z_lo, fit[fit.len() - 1].z_hi)
    }

    /// A short name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::IncidentOverpressure => "incident overpressure",
            Quantity::ReflectedPressure => "reflected pressure",
            Quantity::IncidentImpulse => "incident impulse",
            Quantity::ArrivalTime => "arrival time",
            Quantity::PositiveDuration => "positive-phase duration",
        }
    }
}

/// Why a Kingery–Bulmash value could not be given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KbError {
    /// The charge mass (kg) is not a finite positive number.
    InvalidCharge(f64),
    /// The range (m) is not a finite non-negative number.
    InvalidRange(f64),
    /// The scaled distance `z` (m/kg^(1/3)) lies outside `[min, max]`, the
    /// published range of the fit of `quantity` (or is not a number).
    OutOfRange {
        /// The quantity asked for.
        quantity: Quantity,
        /// The scaled distance given, m/kg^(1/3).
        z: f64,
        /// Lower end of the fit's range, m/kg^(1/3).
        min: f64,
        /// Upper end of the fit's range, m/kg^(1/3).
        max: f64,
    },
}

impl fmt::Display for KbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KbError::InvalidCharge(w) => {
                write!(f, "charge mass {w} kg is not a finite positive number")
            }
            KbError::InvalidRange(r) => {
                write!(f, "range {r} m is not a finite non-negative number")
            }
            KbError::OutOfRange {
                quantity,
                z,
                min,
                max,
            } => write!(
                f,
                "scaled distance {z} m/kg^(1/3) is outside the Kingery-Bulmash \
                 free-air {} fit's range [{min}, {max}]",
                quantity.name()
            ),
        }
    }
}

impl std::error::Error for KbError {}

/// Scaled distance Z = R / W^(1/3), m/kg^(1/3), of a point `range_m` (m)
/// from the centre of `charge_kg` (kg of TNT).
///
/// No checks: a zero or negative charge gives an infinite or negative Z,
/// which every fit here rejects.
pub fn scaled_distance(range_m: f64, charge_kg: f64) -> f64 {
    range_m / charge_kg.cbrt()
}

/// Peak incident (side-on) overpressure P_so, Pa, at scaled distance `z`
/// (m/kg^(1/3)).
///
/// Kingery & Bulmash (1984), spherical free-air burst, incident pressure:
/// K = (−0.214362789151, 1.35034249993), C0…C8, one segment for
/// 0.0531 ≤ Z ≤ 40 m/kg^(1/3); the fit gives kPa (English units: psi, with
/// K0 = −0.756579301809 and C0 = 1.77284970457).
///
/// # Errors
/// [`KbError::OutOfRange`] outside 0.0531–40 m/kg^(1/3).
pub fn incident_overpressure(z: f64) -> Result<f64, KbError> {
    Ok(evaluate(Quantity::IncidentOverpressure, z)? * KPA)
}

/// Peak normally reflected pressure P_r, Pa, at scaled distance `z`
/// (m/kg^(1/3)): the peak on a rigid surface facing the charge, the shock
/// arriving head-on.
///
/// Kingery & Bulmash (1984), spherical free-air burst, normally reflected
/// pressure: K = (−0.214362789151, 1.35034249993), C0…C9, one segment for
/// 0.0531 ≤ Z ≤ 40 m/kg^(1/3); the fit gives kPa (English units: psi, with
/// C0 = 2.39106134946).
///
/// # Errors
/// [`KbError::OutOfRange`] outside 0.0531–40 m/kg^(1/3).
pub fn reflected_pressure(z: f64) -> Result<f64, KbError> {
    Ok(evaluate(Quantity::ReflectedPressure, z)? * KPA)
}

/// Scaled positive-phase incident impulse i_s / W^(1/3), Pa·s/kg^(1/3), at
/// scaled distance `z` (m/kg^(1/3)).
///
/// Kingery & Bulmash (1984), spherical free-air burst, incident impulse, two
/// segments: 0.0531 ≤ Z < 0.792 with K = (2.34723921354, 3.24299066475),
/// C0…C4, and 0.792 ≤ Z ≤ 40 m/kg^(1/3) with K = (−1.75305660315,
/// 2.30629231803), C0…C8. The fit gives kPa·ms/kg^(1/3), which is
/// Pa·s/kg^(1/3) (English units: psi·ms/lb^(1/3), split at
/// 2.0 ft/lb^(1/3)).
///
/// # Errors
/// [`KbError::OutOfRange`] outside 0.0531–40 m/kg^(1/3).
pub fn scaled_incident_impulse(z: f64) -> Result<f64, KbError> {
    Ok(evaluate(Quantity::IncidentImpulse, z)? * KPA_MS)
}

/// Positive-phase incident impulse i_s, Pa·s, at `range_m` (m) from
/// `charge_kg` (kg of TNT): [`scaled_incident_impulse`] times W^(1/3).
///
/// # Errors
/// [`KbError::InvalidRange`] / [`KbError::InvalidCharge`] for a range or
/// charge that is not finite and non-negative / positive;
/// [`KbError::OutOfRange`] when Z = R / W^(1/3) is outside 0.0531–40
/// m/kg^(1/3).
pub fn incident_impulse(range_m: f64, charge_kg: f64) -> Result<f64, KbError> {
    let (z, w13) = checked_scaling(range_m, charge_kg)?;
    Ok(scaled_incident_impulse(z)? * w13)
}

/// Scaled arrival time t_a / W^(1/3), s/kg^(1/3), of the shock at scaled
/// distance `z` (m/kg^(1/3)), counted from detonation.
///
/// Kingery & Bulmash (1984), spherical free-air burst, arrival time:
/// K = (−0.253273111999, 1.37407043777), C0…C7, one segment for
/// 0.0531 ≤ Z ≤ 40 m/kg^(1/3); the fit gives ms/kg^(1/3) (English units:
/// ms/lb^(1/3), with K0 = −0.80501734056 and C0 = −0.0423733936826).
///
/// # Errors
/// [`KbError::OutOfRange`] outside 0.0531–40 m/kg^(1/3).
pub fn scaled_arrival_time(z: f64) -> Result<f64, KbError> {
    Ok(evaluate(Quantity::ArrivalTime, z)? * MS)
}

/// Arrival time t_a, s, of the shock at `range_m` (m) from `charge_kg` (kg
/// of TNT): [`scaled_arrival_time`] times W^(1/3).
///
/// # Errors
/// As [`incident_impulse`], with the arrival-time range 0.0531–40
/// m/kg^(1/3).
pub fn arrival_time(range_m: f64, charge_kg: f64) -> Result<f64, KbError> {
    let (z, w13) = checked_scaling(range_m, charge_kg)?;
    Ok(scaled_arrival_time(z)? * w13)
}

/// Scaled positive-phase duration t_0 / W^(1/3), s/kg^(1/3), at scaled
/// distance `z` (m/kg^(1/3)).
///
/// Kingery & Bulmash (1984), spherical free-air burst, positive-phase
/// duration, three segments: 0.147 ≤ Z < 0.888 with K = (2.26367268496,
/// 5.11588554305), C0…C8; 0.888 ≤ Z < 2.28 with K = (−1.33361206714,
/// 9.2996288611), C0…C8; 2.28 ≤ Z ≤ 40 m/kg^(1/3) with K = (−3.13005805346,
/// 3.1524725364), C0…C7. The fit gives ms/kg^(1/3) (English units:
/// ms/lb^(1/3), 0.37–100 ft/lb^(1/3), split at 2.24 and 5.75).
///
/// # Errors
/// [`KbError::OutOfRange`] outside 0.147–40 m/kg^(1/3).
pub fn scaled_positive_duration(z: f64) -> Result<f64, KbError> {
    Ok(evaluate(Quantity::PositiveDuration, z)? * MS)
}

/// Positive-phase duration t_0, s, at `range_m` (m) from `charge_kg` (kg of
/// TNT): [`scaled_positive_duration`] times W^(1/3).
///
/// # Errors
/// As [`incident_impulse`], with the duration range 0.147–40 m/kg^(1/3).
pub fn positive_duration(range_m: f64, charge_kg: f64) -> Result<f64, KbError> {
    let (z, w13) = checked_scaling(range_m, charge_kg)?;
    Ok(scaled_positive_duration(z)? * w13)
}

/// Pa per kPa.
const KPA: f64 = 1.0e3;
/// Pa·s per kPa·ms.
const KPA_MS: f64 = 1.0;
/// s per ms.
const MS: f64 = 1.0e-3;

/// Z and W^(1/3) for a range (m) and charge (kg), both checked.
fn checked_scaling(range_m: f64, charge_kg: f64) -> Result<(f64, f64), KbError> {
    if !(charge_kg.is_finite() && charge_kg > 0.0) {
        return Err(KbError::InvalidCharge(charge_kg));
    }
    if !(range_m.is_finite() && range_m >= 0.0) {
        return Err(KbError::InvalidRange(range_m));
    }
    let w13 = charge_kg.cbrt();
    Ok((range_m / w13, w13))
}

/// One polynomial of a fit, valid for `z_lo <= Z < z_hi` (Z in m/kg^(1/3)).
#[derive(Debug)]
struct Segment {
    z_lo: f64,
    z_hi: f64,
    /// K0, K1 of U = K0 + K1 log10 Z.
    k: [f64; 2],
    /// C0, C1, … of log10 Y = Σ Cᵢ Uⁱ, Y in the fit's metric unit.
    c: &'static [f64],
}

impl Segment {
    /// Y in the fit's metric unit (kPa, kPa·ms/kg^(1/3) or ms/kg^(1/3)).
    fn eval(&self, z: f64) -> f64 {
        let u = self.k[0] + self.k[1] * z.log10();
        let log_y = self.c.iter().rev().fold(0.0, |acc, &ci| acc * u + ci);
        10f64.powf(log_y)
    }
}

/// The segments of a quantity's fit, in increasing Z.
fn fit(q: Quantity) -> &'static [Segment] {
    match q {
        Quantity::IncidentOverpressure => &INCIDENT_OVERPRESSURE,
        Quantity::ReflectedPressure => &REFLECTED_PRESSURE,
        Quantity::IncidentImpulse => &INCIDENT_IMPULSE,
        Quantity::ArrivalTime => &ARRIVAL_TIME,
        Quantity::PositiveDuration => &POSITIVE_DURATION,
    }
}

/// The fit of `q` at `z`, in its metric unit, or the range error.
fn evaluate(q: Quantity, z: f64) -> Result<f64, KbError> {
    let segments = fit(q);
    let (min, max) = q.valid_range();
    // Written so that NaN fails too.
    if !(z >= min && z <= max) {
        return Err(KbError::OutOfRange {
            quantity: q,
            z,
            min,
            max,
        });
    }
    let last = segments.len() - 1;
    let segment = segments
        .iter()
        .enumerate()
        .find(|(i, s)| z < s.z_hi || *i == last)
        .map_or(&segments[last], |(_, s)| s);
    Ok(segment.eval(z))
}

// Coefficients: Kingery & Bulmash (1984), spherical free-air burst, metric
// units, as transcribed in `lightsquared/kingery_bulmash`
// (`1_configuration/models/kb_old.py`), corrected where the English-unit
// identities show a transcription slip (see the module docs).

const INCIDENT_OVERPRESSURE: [Segment; 1] = [Segment {
    z_lo: 0.0531,
    z_hi: 40.0,
    k: [-0.214362789151, 1.35034249993],
    c: &[
        2.611368669,
        -1.69012801396,
        0.00804973591951,
        0.336743114941,
        -0.00516226351334,
        -0.0809228619888,
        -0.00478507266747,
        0.00793030472242,
        0.0007684469735,
    ],
}];

const REFLECTED_PRESSURE: [Segment; 1] = [Segment {
    z_lo: 0.0531,
    z_hi: 40.0,
    k: [-0.214362789151, 1.35034249993],
    c: &[
        3.22958031387,
        -2.21400538997,
        0.035119031446,
        0.657599992109,
        0.0141818951887,
        -0.243076636231,
        -0.0158699803158,
        0.0492741184234,
        0.00227639644004,
        -0.00397126276058,
    ],
}];

const INCIDENT_IMPULSE: [Segment; 2] = [
    Segment {
        z_lo: 0.0531,
        z_hi: 0.792,
        k: [2.34723921354, 3.24299066475],
        c: &[
            2.38830516757,
            -0.443749377691,
            0.168825414684,
            0.0348138030308,
            -0.010435192824,
        ],
    },
    Segment {
        z_lo: 0.792,
        z_hi: 40.0,
        k: [-1.75305660315, 2.30629231803],
        c: &[
            1.55197227115,
            -0.40463292088,
            -0.0142721946082,
            0.00912366316617,
            -0.0006750681404,
            -0.00800863718901,
            0.00314819515931,
            0.00152044783382,
            -0.0007470265899,
        ],
    },
];

const ARRIVAL_TIME: [Segment; 1] = [Segment {
    z_lo: 0.0531,
    z_hi: 40.0,
    k: [-0.253273111999, 1.37407043777],
    c: &[
        0.0720707787637,
        1.36456871214,
        -0.0570035692784,
        -0.182832224796,
        0.0118851436014,
        0.0432648687627,
        -0.0007997367834,
        -0.00436073555033,
    ],
}];

const POSITIVE_DURATION: [Segment; 3] = [
    Segment {
        z_lo: 0.147,
        z_hi: 0.888,
        k: [2.26367268496, 5.11588554305],
        c: &[
            -0.686608550419,
            0.164953518069,
            0.127788499497,
            0.00291430135946,
            0.00187957449227,
            0.0173413962543,
            0.00269739758043,
            -0.00361976502798,
            -0.00100926577934,
        ],
    },
    Segment {
        z_lo: 0.888,
        z_hi: 2.28,
        k: [-1.33361206714, 9.2996288611],
        c: &[
            0.23031841078,
            -0.0297944268969,
            0.0306329542941,
            0.0183405574074,
            -0.0173964666286,
            -0.00106321963576,
            0.0056206003128,
            0.0001618217499,
            -0.0006860188944,
        ],
    },
    Segment {
        z_lo: 2.28,
        z_hi: 40.0,
        k: [-3.13005805346, 3.1524725364],
        c: &[
            0.621036276475,
            0.0967031995552,
            -0.00801302059667,
            0.00482705779732,
            0.00187587272287,
            -0.00246738509321,
            -0.000841116668,
            0.0006193291052,
        ],
    },
];

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The Z values E-FREEAIR reports at, m/kg^(1/3).
    const CASE_Z: [f64; 7] = [0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0];

    fn rel(a: f64, b: f64) -> f64 {
        (a / b - 1.0).abs()
    }

    // ------------------------------------------------------------------
    // The English-unit transcription (ConWep air burst as coded in AERO-S,
    // `packages/aeros/Utils.d/Conwep.d/BlastLoading.C`), written out here
    // on its own so that it checks this module's metric coefficients rather
    // than restating them. Z in ft/lb^(1/3), splits in log10 Z; results in
    // psi, psi·ms/lb^(1/3), ms/lb^(1/3).
    // ------------------------------------------------------------------

    const FT: f64 = 0.3048; // m
    const LB: f64 = 0.453_592_37; // kg
    const PSI_KPA: f64 = 6.894_757_293_168; // kPa per psi

    /// (log10 Z upper bound of the segment, K0, K1, C0…) in English units.
    type EnglishSegment = (f64, f64, f64, &'static [f64]);

    const EN_PSO: [EnglishSegment; 1] = [(
        f64::INFINITY,
        -0.756579301809,
        1.35034249993,
        &[
            1.77284970457,
            -1.69012801396,
            0.00804973591951,
            0.336743114941,
            -0.00516226351334,
            -0.0809228619888,
            -0.00478507266747,
            0.00793030472242,
            0.0007684469735,
        ],
    )];
    const EN_PR: [EnglishSegment; 1] = [(
        f64::INFINITY,
        -0.756579301809,
        1.35034249993,
        &[
            2.39106134946,
            -2.21400538997,
            0.035119031446,
            0.657599992109,
            0.0141818951887,
            -0.243076636231,
            -0.0158699803158,
            0.0492741184234,
            0.00227639644004,
            -0.00397126276058,
        ],
    )];
    // The split is the source's 0.30103 (log10 2 ft/lb^(1/3) as printed).
    #[allow(clippy::approx_constant)]
    const EN_IS: [EnglishSegment; 2] = [
        (
            0.30103,
            1.04504877747,
            3.24299066475,
            &[
                1.43534136453,
                -0.443749377691,
                0.168825414684,
                0.0348138030308,
                -0.010435192824,
            ],
        ),
        (
            f64::INFINITY,
            -2.67912519532,
            2.30629231803,
            &[
                0.599008468099,
                -0.40463292088,
                -0.0142721946082,
                0.00912366316617,
                -0.0006750681404,
                -0.00800863718901,
                0.00314819515931,
                0.00152044783382,
                -0.0007470265899,
            ],
        ),
    ];
    const EN_TA: [EnglishSegment; 1] = [(
        f64::INFINITY,
        -0.80501734056,
        1.37407043777,
        &[
            -0.0423733936826,
            1.36456871214,
            -0.0570035692784,
            -0.182832224796,
            0.0118851436014,
            0.0432648687627,
            -0.0007997367834,
            -0.00436073555033,
        ],
    )];
    // The third slope is the identity-checked 3.1524725364 (the AERO-S copy
    // has 3.1524725264; the difference moves U by < 2·10⁻⁸ here).
    const EN_TD: [EnglishSegment; 3] = [
        (
            0.350248,
            0.209440059933,
            5.11588554305,
            &[
                -0.801052722864,
                0.164953518069,
                0.127788499497,
                0.00291430135946,
                0.00187957449227,
                0.0173413962543,
                0.00269739758043,
                -0.00361976502798,
                -0.00100926577934,
            ],
        ),
        (
            0.7596678,
            -5.06778493835,
            9.2996288611,
            &[
                0.115874238335,
                -0.0297944268969,
                0.0306329542941,
                0.018340557407,
                -0.0173964666286,
                -0.00106321963576,
                0.0056206003128,
                0.0001618217499,
                -0.0006860188944,
            ],
        ),
        (
            f64::INFINITY,
            -4.39590184126,
            3.1524725364,
            &[
                0.50659210403,
                0.0967031995552,
                -0.00801302059667,
                0.00482705779732,
                0.00187587272287,
                -0.00246738509321,
                -0.000841116668,
                0.0006193291052,
            ],
        ),
    ];

    /// The English-unit fit at metric `z` (m/kg^(1/3)), converted to SI
    /// (Pa, Pa·s/kg^(1/3), s/kg^(1/3)).
    fn english(q: Quantity, z: f64) -> f64 {
        // ft/lb^(1/3) per m/kg^(1/3), and kg^(1/3) per lb^(1/3).
        let z_ft = z / FT * LB.cbrt();
        let per_lb13_to_per_kg13 = LB.cbrt().recip();
        let (segments, to_si): (&[EnglishSegment], f64) = match q {
            Quantity::IncidentOverpressure => (&EN_PSO, PSI_KPA * 1e3),
            Quantity::ReflectedPressure => (&EN_PR, PSI_KPA * 1e3),
            // psi·ms/lb^(1/3) → kPa·ms/kg^(1/3) = Pa·s/kg^(1/3).
            Quantity::IncidentImpulse => (&EN_IS, PSI_KPA * per_lb13_to_per_kg13),
            Quantity::ArrivalTime | Quantity::PositiveDuration => (
                if q == Quantity::ArrivalTime {
                    &EN_TA
                } else {
                    &EN_TD
                },
                1e-3 * per_lb13_to_per_kg13,
            ),
        };
        let t = z_ft.log10();
        let &(_, k0, k1, c) = segments
            .iter()
            .find(|s| t <= s.0)
            .expect("the last segment has no upper bound");
        let u = k0 + k1 * t;
        let log_y = c.iter().rev().fold(0.0, |acc, &ci| acc * u + ci);
        10f64.powf(log_y) * to_si
    }

    fn si(q: Quantity, z: f64) -> f64 {
        match q {
            Quantity::IncidentOverpressure => incident_overpressure(z),
            Quantity::ReflectedPressure => reflected_pressure(z),
            Quantity::IncidentImpulse => scaled_incident_impulse(z),
            Quantity::ArrivalTime => scaled_arrival_time(z),
            Quantity::PositiveDuration => scaled_positive_duration(z),
        }
        .unwrap()
    }

    /// (a) The metric coefficients against the independently written
    /// English-unit set: one fit, converted by the unit factors. The
    /// conversion constants of the two transcriptions differ in the sixth
    /// or seventh digit (K0 and C0 are consistent to 3·10⁻⁶ in log10);
    /// measured agreement ≤ 4·10⁻⁶ relative, so 1·10⁻⁵ is asked. The two
    /// sets place their splits at slightly different Z (0.792 vs 0.7934,
    /// 0.888 vs 0.8886, 2.28 vs 2.2810 m/kg^(1/3)), and below
    /// 0.457 ft/lb^(1/3) the AERO-S routine uses a constant duration instead
    /// of the first duration segment: those slivers are left out of the
    /// sweep (the duration is compared from Z = 0.19 m/kg^(1/3)).
    #[test]
    fn english_unit_transcription_agrees() {
        let slivers = [(0.79, 0.7945), (0.887, 0.8895), (2.279, 2.2815)];
        let mut worst = 0.0_f64;
        for q in Quantity::ALL {
            let (min, max) = q.valid_range();
            let min = if q == Quantity::PositiveDuration {
                0.19
            } else {
                min
            };
            let n = 2000;
            let sweep = (0..=n).map(|j| min * (max / min).powf(j as f64 / n as f64));
            for z in CASE_Z.into_iter().chain(sweep) {
                if slivers.iter().any(|&(a, b)| z > a && z < b) {
                    continue;
                }
                let r = rel(si(q, z), english(q, z));
                worst = worst.max(r);
                assert!(r < 1e-5, "{} at Z = {z}: rel. diff {r:e}", q.name());
            }
        }
        assert!(worst > 0.0);
    }

    /// (a) Against the OpenRadioss free-air tables ("figure 2_7",
    /// `common_source/modules/loads/pblast_mod.F90`, g–cm–µs–Mbar): values at
    /// the grid points Z_i = 0.05 · 800^(i/255) m/kg^(1/3) nearest the case's
    /// Z = 0.5, 1, 2, 3, 5, 10, 20. Unit factors to SI: 1 Mbar = 10¹¹ Pa;
    /// scaled impulse 1 Mbar·µs/g^(1/3) = 10⁶ Pa·s/kg^(1/3); scaled time
    /// 1 µs/g^(1/3) = 10⁻⁵ s/kg^(1/3). The tables carry 11 digits but were
    /// evaluated with other conversion constants; measured agreement
    /// ≤ 4.3·10⁻⁵ relative, so 1·10⁻⁴ is asked.
    #[test]
    fn openradioss_tables_agree() {
        const IDX: [i32; 7] = [88, 114, 141, 156, 176, 202, 229];
        const PSO: [f64; 7] = [
            0.38544251883e-4,
            0.95021561164e-5,
            0.19152228662e-5,
            0.82417363879e-6,
            0.30846257740e-6,
            0.11136583151e-6,
            0.43818297429e-7,
        ];
        const PR: [f64; 7] = [
            0.30069230737e-3,
            0.51127437367e-4,
            0.63239171549e-5,
            0.21818971509e-5,
            0.68904777793e-6,
            0.23411634742e-6,
            0.88873697645e-7,
        ];
        const IS: [f64; 7] = [
            0.14149969858e-3,
            0.17551666935e-3,
            0.91514411357e-4,
            0.64611134135e-4,
            0.40300656744e-4,
            0.21192924243e-4,
            0.10629102621e-4,
        ];
        const TA: [f64; 7] = [
            15.518552639,
            52.462757520,
            197.01809844,
            395.40821833,
            910.92275354,
            2263.7863858,
            5164.5180288,
        ];
        for (k, &i) in IDX.iter().enumerate() {
            let z = 0.05 * 800f64.powf(f64::from(i) / 255.0);
            let checks = [
                ("P_so", incident_overpressure(z).unwrap(), PSO[k] * 1e11),
                ("P_r", reflected_pressure(z).unwrap(), PR[k] * 1e11),
                (
                    "i_s/W^1/3",
                    scaled_incident_impulse(z).unwrap(),
                    IS[k] * 1e6,
                ),
                ("t_a/W^1/3", scaled_arrival_time(z).unwrap(), TA[k] * 1e-5),
            ];
            for (name, ours, table) in checks {
                let r = rel(ours, table);
                assert!(r < 1e-4, "{name} at Z = {z}: ours {ours}, table {table}");
            }
        }
    }

    /// The values quoted in the module docs (5 significant figures), so the
    /// table there stays what the code computes.
    #[test]
    fn documented_table() {
        let rows: [[f64; 6]; 7] = [
            [0.5, 3884.8, 141.29, 0.15408, 0.31965, 30360.0],
            [1.0, 934.86, 174.54, 0.53184, 1.7949, 5005.6],
            [2.0, 194.67, 92.122, 1.9440, 1.8459, 645.83],
            [3.0, 81.589, 64.331, 3.9874, 2.6846, 215.50],
            [5.0, 31.296, 40.619, 8.9953, 3.3334, 70.023],
            [10.0, 11.091, 21.131, 22.722, 4.1995, 23.313],
            [20.0, 4.4512, 10.752, 50.968, 5.1425, 9.0327],
        ];
        for [z, pso, is, ta, td, pr] in rows {
            // W = 1 kg at R = z m.
            let got = [
                incident_overpressure(z).unwrap() / 1e3,
                incident_impulse(z, 1.0).unwrap(),
                arrival_time(z, 1.0).unwrap() * 1e3,
                positive_duration(z, 1.0).unwrap() * 1e3,
                reflected_pressure(z).unwrap() / 1e3,
            ];
            for (g, want) in got.into_iter().zip([pso, is, ta, td, pr]) {
                assert!(rel(g, want) < 6e-5, "Z = {z}: {g} vs {want}");
            }
        }
    }

    /// (b) The published segments do not meet exactly; the steps are
    /// measured and pinned: impulse −0.40 % at 0.792, duration +0.92 % at
    /// 0.888 and +0.086 % at 2.28 m/kg^(1/3). Each bound is the measured
    /// step plus a little, so a changed coefficient shows here.
    #[test]
    fn joins_are_nearly_continuous() {
        let cases = [
            (&INCIDENT_IMPULSE[0], &INCIDENT_IMPULSE[1], -0.00404, 1e-4),
            (&POSITIVE_DURATION[0], &POSITIVE_DURATION[1], 0.00918, 1e-4),
            (&POSITIVE_DURATION[1], &POSITIVE_DURATION[2], 0.000865, 1e-5),
        ];
        for (below, above, step, tol) in cases {
            let z = below.z_hi;
            assert_eq!(z, above.z_lo);
            let jump = above.eval(z) / below.eval(z) - 1.0;
            assert!((jump - step).abs() < tol, "join at {z}: {jump}");
            assert!(jump.abs() < 0.01);
        }
        // At a split the public function uses the upper segment.
        let z = INCIDENT_IMPULSE[1].z_lo;
        assert_eq!(
            scaled_incident_impulse(z).unwrap(),
            INCIDENT_IMPULSE[1].eval(z) * KPA_MS
        );
    }

    /// (c) Monotone where the physics requires it, on a fine sweep of each
    /// fit's range: overpressure and reflected pressure fall with Z, the
    /// arrival time rises; the impulse falls beyond its near-field hump
    /// (Z ≥ 0.792).
    #[test]
    fn monotone_on_sweeps() {
        let n = 20_000;
        let sweep = |lo: f64, hi: f64| {
            (0..=n).map(move |j| (lo * (hi / lo).powf(j as f64 / n as f64)).min(hi))
        };
        let check = |f: fn(f64) -> Result<f64, KbError>, lo, hi, falls: bool| {
            let mut prev: Option<f64> = None;
            for z in sweep(lo, hi) {
                let v = f(z).unwrap();
                if let Some(p) = prev {
                    assert!(if falls { v <= p } else { v >= p }, "at Z = {z}");
                }
                prev = Some(v);
            }
        };
        check(incident_overpressure, 0.0531, 40.0, true);
        check(reflected_pressure, 0.0531, 40.0, true);
        check(scaled_arrival_time, 0.0531, 40.0, false);
        check(scaled_incident_impulse, 0.792, 40.0, true);
    }

    /// Physics: the shock speed implied by the arrival-time fit,
    /// dR/dt_a = 1 / (d(t_a/W^(1/3))/dZ), against the Rankine–Hugoniot
    /// speed of a shock of the fitted overpressure in sea-level air,
    /// U = c₀ √(1 + (γ+1)/(2γ) · P_so/p₀). The two fits were made separately
    /// and differentiating the arrival-time fit brings out its small
    /// wiggles; measured worst case 2.53 % (at Z ≈ 0.54) over
    /// Z = 0.5–20 m/kg^(1/3), the case's span, so 3 % is asked. (Towards
    /// the top of the arrival-time fit's range the slope drifts: 7 % at
    /// Z = 40.)
    #[test]
    fn arrival_time_matches_rankine_hugoniot() {
        let (gamma, p0, c0) = (1.4, 101_325.0, 340.29);
        let n = 2000;
        let mut worst = 0.0_f64;
        for j in 0..=n {
            let z = 0.5 * 40f64.powf(j as f64 / n as f64);
            let h = 1e-5 * z;
            let dtdz = (scaled_arrival_time(z + h).unwrap() - scaled_arrival_time(z - h).unwrap())
                / (2.0 * h);
            let u_fit = 1.0 / dtdz;
            let p = incident_overpressure(z).unwrap();
            let u_rh = c0 * (1.0 + (gamma + 1.0) / (2.0 * gamma) * p / p0).sqrt();
            worst = worst.max(rel(u_fit, u_rh));
        }
        assert!(worst < 0.03, "worst {worst}");
    }

    /// (d) Out of range, non-finite or non-physical input: an error, never
    /// a panic.
    #[test]
    fn out_of_range_is_an_error() {
        for q in Quantity::ALL {
            let (min, max) = q.valid_range();
            for z in [
                0.0,
                -1.0,
                min * 0.999,
                max * 1.001,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ] {
                let got = match q {
                    Quantity::IncidentOverpressure => incident_overpressure(z),
                    Quantity::ReflectedPressure => reflected_pressure(z),
                    Quantity::IncidentImpulse => scaled_incident_impulse(z),
                    Quantity::ArrivalTime => scaled_arrival_time(z),
                    Quantity::PositiveDuration => scaled_positive_duration(z),
                };
                match got {
                    Err(KbError::OutOfRange {
                        quantity,
                        min: lo,
                        max: hi,
                        ..
                    }) => {
                        assert_eq!(quantity, q);
                        assert_eq!((lo, hi), (min, max));
                    }
                    other => panic!("{} at Z = {z}: {other:?}", q.name()),
                }
            }
            // Both ends are inside.
            assert!(si(q, min).is_finite() && si(q, max).is_finite());
        }
        assert_eq!(
            scaled_positive_duration(0.1).unwrap_err(),
            KbError::OutOfRange {
                quantity: Quantity::PositiveDuration,
                z: 0.1,
                min: 0.147,
                max: 40.0
            }
        );
        assert_eq!(incident_impulse(1.0, 0.0), Err(KbError::InvalidCharge(0.0)));
        assert!(matches!(
            arrival_time(1.0, f64::NAN),
            Err(KbError::InvalidCharge(_))
        ));
        assert_eq!(
            positive_duration(-1.0, 1.0),
            Err(KbError::InvalidRange(-1.0))
        );
        assert!(matches!(
            arrival_time(100.0, 1.0),
            Err(KbError::OutOfRange { .. })
        ));
        let msg = incident_overpressure(50.0).unwrap_err().to_string();
        assert!(msg.contains("incident overpressure") && msg.contains("40"));
    }

    /// Scaling by hand: 8 kg at 2 m is Z = 1 m/kg^(1/3), and the absolute
    /// impulse and times are twice the scaled ones (W^(1/3) = 2 kg^(1/3)).
    #[test]
    fn hopkinson_cranz_scaling() {
        assert_eq!(scaled_distance(2.0, 8.0), 1.0);
        assert_eq!(scaled_distance(3.0, 1.0), 3.0);
        let z = 1.0;
        assert!(
            rel(
                incident_impulse(2.0, 8.0).unwrap(),
                2.0 * scaled_incident_impulse(z).unwrap()
            ) < 1e-14
        );
        assert!(
            rel(
                arrival_time(2.0, 8.0).unwrap(),
                2.0 * scaled_arrival_time(z).unwrap()
            ) < 1e-14
        );
        assert!(
            rel(
                positive_duration(2.0, 8.0).unwrap(),
                2.0 * scaled_positive_duration(z).unwrap()
            ) < 1e-14
        );
    }

    proptest! {
        /// (c) For any two distances in range, the nearer sees the higher
        /// overpressure and reflected pressure and the earlier arrival, and
        /// beyond the impulse hump the larger impulse.
        #[test]
        fn monotone_pairs(a in 0.0531f64..=40.0, b in 0.0531f64..=40.0) {
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            let pso = |z| incident_overpressure(z).unwrap();
            let pr = |z| reflected_pressure(z).unwrap();
            let ta = |z| scaled_arrival_time(z).unwrap();
            let is = |z| scaled_incident_impulse(z).unwrap();
            prop_assert!(pso(near) >= pso(far));
            prop_assert!(pr(near) >= pr(far));
            prop_assert!(ta(near) <= ta(far));
            if near >= 0.792 {
                prop_assert!(is(near) >= is(far));
            }
            // Reflection at least doubles the incident overpressure.
            prop_assert!(pr(near) >= 2.0 * pso(near));
        }

        /// Any finite input: a value or an error, no panic, and a value is
        /// finite and positive.
        #[test]
        fn never_panics(z in proptest::num::f64::ANY) {
            for q in Quantity::ALL {
                let got = match q {
                    Quantity::IncidentOverpressure => incident_overpressure(z),
                    Quantity::ReflectedPressure => reflected_pressure(z),
                    Quantity::IncidentImpulse => scaled_incident_impulse(z),
                    Quantity::ArrivalTime => scaled_arrival_time(z),
                    Quantity::PositiveDuration => scaled_positive_duration(z),
                };
                if let Ok(v) = got {
                    prop_assert!(v.is_finite() && v > 0.0);
                }
            }
        }
    }
}
