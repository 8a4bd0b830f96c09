//! Exact solution of the Riemann problem between two stiffened gases
//! (Toro 2009, ch. 4, with p replaced by p + p∞ on each side; Ivings,
//! Causon & Toro 1998). The reference solution of V-WATER-AIR-ICE.
//!
//! The star pressure p* solves f_L(p*) + f_R(p*) + u_R − u_L = 0 with, for
//! side K (γ, p∞, ρ_K, p_K, c_K² = γ(p_K + p∞)/ρ_K),
//! shock (p > p_K):   f_K = (p − p_K) √(A_K/(p + p∞ + B_K)),
//!                    A_K = 2/((γ + 1)ρ_K), B_K = (γ − 1)(p_K + p∞)/(γ + 1);
//! rarefaction:       f_K = 2c_K/(γ − 1) [((p + p∞)/(p_K + p∞))^((γ−1)/2γ) − 1],
//! solved by a safeguarded Newton iteration (Toro §4.3.2).

/// One side of the Riemann problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiemannSide {
    /// γ.
    pub gamma: f64,
    /// p∞, Pa.
    pub p_inf: f64,
    /// Density, kg/m³.
    pub rho: f64,
    /// Velocity, m/s.
    pub u: f64,
    /// Pressure, Pa.
    pub p: f64,
}

impl RiemannSide {
    fn c(&self) -> f64 {
        (self.gamma * (self.p + self.p_inf) / self.rho).sqrt()
    }

    /// f_K(p) and its derivative.
    fn f(&self, p: f64) -> (f64, f64) {
        let g = self.gamma;
        let (pk, pi) = (self.p + self.p_inf, p + self.p_inf);
        if p > self.p {
            let a = 2.0 / ((g + 1.0) * self.rho);
            let b = (g - 1.0) / (g + 1.0) * pk;
            let q = (a / (pi + b)).sqrt();
            ((p - self.p) * q, q * (1.0 - 0.5 * (p - self.p) / (pi + b)))
        } else {
            let c = self.c();
            let r = pi / pk;
            let ex = (g - 1.0) / (2.0 * g);
            (
                2.0 * c / (g - 1.0) * (r.powf(ex) - 1.0),
                r.powf(-(g + 1.0) / (2.0 * g)) / (self.rho * c),
            )
        }
    }
}

/// The solved star state; [`ExactRiemann::sample`] gives the solution at
/// any x/t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactRiemann {
    /// Left state.
    pub left: RiemannSide,
    /// Right state.
    pub right: RiemannSide,
    /// Star pressure, Pa.
    pub p_star: f64,
    /// Star (contact) velocity, m/s.
    pub u_star: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// A sampled state (ρ, u, p).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Primitive {
    /// Density, kg/m³.
    pub rho: f64,
    /// Velocity, m/s.
    pub u: f64,
    /// Pressure, Pa.
    pub p: f64,
}

impl ExactRiemann {
    /// Solves for p* to a relative change of 1e-14; an error names what
    /// is wrong (vacuum, a bad state, no convergence).
    pub fn solve(left: RiemannSide, right: RiemannSide) -> Result<Self, String> {
        for (name, s) in [("left", left), ("right", right)] {
            if !(s.gamma > 1.0 && s.rho > 0.0 && s.p + s.p_inf > 0.0 && s.u.is_finite()) {
                return Err(format!("riemann: bad {name} state {s:?}"));
            }
        }
        let du = right.u - left.u;
        if 2.0 * left.c() / (left.gamma - 1.0) + 2.0 * right.c() / (right.gamma - 1.0) <= du {
            return Err("riemann: the states create a vacuum".into());
        }
        // Star pressure must keep p + p∞ > 0 on both sides.
        let floor = -left.p_inf.min(right.p_inf);
        let mut p = 0.5 * (left.p + right.p);
        for it in 1..=100 {
            let (fl, dl) = left.f(p);
            let (fr, dr) = right.f(p);
            let mut next = p - (fl + fr + du) / (dl + dr);
            if next <= floor {
                next = 0.5 * (p + floor);
            }
            let change = 2.0 * (next - p).abs() / (next.abs() + p.abs());
            p = next;
            if change < 1e-14 {
                let u = 0.5 * (left.u + right.u) + 0.5 * (right.f(p).0 - left.f(p).0);
                return Ok(Self {
                    left,
                    right,
                    p_star: p,
                    u_star: u,
                    iterations: it,
                });
            }
        }
        Err("riemann: Newton iteration on p* did not converge in 100 iterations".into())
    }

    /// Star density on side `s` of the contact (shock: Rankine–Hugoniot;
    /// rarefaction: isentrope).
    fn star_density(&self, s: &RiemannSide) -> f64 {
        let g = s.gamma;
        let r = (self.p_star + s.p_inf) / (s.p + s.p_inf);
        if self.p_star > s.p {
            let k = (g - 1.0) / (g + 1.0);
            s.rho * (r + k) / (k * r + 1.0)
        } else {
            s.rho * r.powf(1.0 / g)
        }
    }

    /// Shock speeds (left, right); None where that wave is a rarefaction.
    pub fn shock_speeds(&self) -> [Option<f64>; 2] {
        let speed = |s: &RiemannSide, sign: f64| {
            (self.p_star > s.p).then(|| {
                let g = s.gamma;
                let r = (self.p_star + s.p_inf) / (s.p + s.p_inf);
                s.u + sign * s.c() * ((g + 1.0) / (2.0 * g) * (r - 1.0) + 1.0).sqrt()
            })
        };
        [speed(&self.left, -1.0), speed(&self.right, 1.0)]
    }

    /// The solution at similarity coordinate ξ = x/t (Toro §4.5).
    pub fn sample(&self, xi: f64) -> Primitive {
        // Mirror the right side onto the left so one branch does both.
        let (s, sign) = if xi <= self.u_star {
            (self.left, 1.0)
        } else {
            (self.right, -1.0)
        };
        let (u, us, xi) = (sign * s.u, sign * self.u_star, sign * xi);
        let c = s.c();
        let g = s.gamma;
        let star = Primitive {
            rho: self.star_density(&s),
            u: sign * us,
            p: self.p_star,
        };
        let outer = Primitive {
            rho: s.rho,
            u: sign * u,
            p: s.p,
        };
        if self.p_star > s.p {
            let r = (self.p_star + s.p_inf) / (s.p + s.p_inf);
            let shock = u - c * ((g + 1.0) / (2.0 * g) * (r - 1.0) + 1.0).sqrt();
            if xi < shock {
                outer
            } else {
                star
            }
        } else {
            let head = u - c;
            let c_star =
                c * ((self.p_star + s.p_inf) / (s.p + s.p_inf)).powf((g - 1.0) / (2.0 * g));
            let tail = us - c_star;
            if xi < head {
                outer
            } else if xi > tail {
                star
            } else {
                // Inside the fan: u − c = ξ along the characteristic.
                let cf = 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * (u - xi));
                let uf = cf + xi;
                let ratio = cf / c;
                Primitive {
                    rho: s.rho * ratio.powf(2.0 / (g - 1.0)),
                    u: sign * uf,
                    p: (s.p + s.p_inf) * ratio.powf(2.0 * g / (g - 1.0)) - s.p_inf,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn side(gamma: f64, p_inf: f64, rho: f64, u: f64, p: f64) -> RiemannSide {
        RiemannSide {
            gamma,
            p_inf,
            rho,
            u,
            p,
        }
    }

    /// Toro 2009 Table 4.2/4.3, test 1 (Sod): p* = 0.30313, u* = 0.92745,
    /// ρ*L = 0.42632, ρ*R = 0.26557.
    #[test]
    fn sod_star_state_matches_toro() {
        let r = ExactRiemann::solve(
            side(1.4, 0.0, 1.0, 0.0, 1.0),
            side(1.4, 0.0, 0.125, 0.0, 0.1),
        )
        .unwrap();
        assert!((r.p_star - 0.30313).abs() < 1e-5, "{}", r.p_star);
        assert!((r.u_star - 0.92745).abs() < 1e-5, "{}", r.u_star);
        let l = r.sample(r.u_star - 1e-9);
        let rr = r.sample(r.u_star + 1e-9);
        assert!((l.rho - 0.42632).abs() < 1e-5, "{}", l.rho);
        assert!((rr.rho - 0.26557).abs() < 1e-5, "{}", rr.rho);
        // Toro test 1 shock speed 1.75216.
        assert!((r.shock_speeds()[1].unwrap() - 1.75216).abs() < 1e-5);
        assert!(r.shock_speeds()[0].is_none());
    }

    /// Toro test 3 (strong left blast): p* = 460.894, u* = 19.5975.
    #[test]
    fn toro_test_3_star_state() {
        let r = ExactRiemann::solve(
            side(1.4, 0.0, 1.0, 0.0, 1000.0),
            side(1.4, 0.0, 1.0, 0.0, 0.01),
        )
        .unwrap();
        assert!((r.p_star - 460.894).abs() < 1e-3, "{}", r.p_star);
        assert!((r.u_star - 19.5975).abs() < 1e-4, "{}", r.u_star);
    }

    /// With the same p∞ on both sides, the problem in p + p∞ is the ideal
    /// gas one: shifting Sod by p∞ shifts p* and leaves u* and ρ* alone.
    #[test]
    fn common_p_inf_is_a_pressure_shift() {
        let pinf = 3.0;
        let r = ExactRiemann::solve(
            side(1.4, pinf, 1.0, 0.0, 1.0 - pinf),
            side(1.4, pinf, 0.125, 0.0, 0.1 - pinf),
        )
        .unwrap();
        assert!((r.p_star + pinf - 0.30313).abs() < 1e-5, "{}", r.p_star);
        assert!((r.u_star - 0.92745).abs() < 1e-5);
    }

    /// Water–air tube: the right shock and the left rarefaction's states
    /// satisfy the jump conditions and the isentrope, and the velocity is
    /// continuous at the contact.
    #[test]
    fn water_air_jumps_hold() {
        let (l, rt) = (
            side(4.4, 6e8, 1000.0, 0.0, 1e9),
            side(1.4, 0.0, 50.0, 0.0, 1e5),
        );
        let r = ExactRiemann::solve(l, rt).unwrap();
        assert!(r.p_star > rt.p && r.p_star < l.p);
        let s = r.shock_speeds()[1].unwrap();
        let star = r.sample(r.u_star + 1e-6);
        // Mass: ρ_R (s − u_R) = ρ* (s − u*); momentum: p + ρ(u − s)².
        let m = rt.rho * s;
        assert!((m - star.rho * (s - star.u)).abs() < 1e-9 * m);
        let mom = |q: Primitive| q.p + q.rho * (q.u - s).powi(2);
        let outer = Primitive {
            rho: rt.rho,
            u: 0.0,
            p: rt.p,
        };
        assert!((mom(outer) - mom(star)).abs() < 1e-9 * mom(star));
        // Left star state on the water isentrope (p + p∞)/ρ^γ.
        let ls = r.sample(r.u_star - 1e-6);
        let k = |q: Primitive| (q.p + 6e8) / q.rho.powf(4.4);
        assert!(
            (k(ls)
                / k(Primitive {
                    rho: 1000.0,
                    u: 0.0,
                    p: 1e9
                })
                - 1.0)
                .abs()
                < 1e-12
        );
        assert!((ls.u - star.u).abs() < 1e-9 * star.u.abs());
        // The fan joins continuously at its tail.
        let c_star = (4.4 * (r.p_star + 6e8) / ls.rho).sqrt();
        let tail = r.sample(r.u_star - c_star - 1e-9);
        assert!((tail.p - r.p_star).abs() < 1e-6 * r.p_star);
    }
}
