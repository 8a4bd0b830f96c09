//! The exact solution of the Riemann problem for the one-dimensional Euler
//! equations of a Noble–Abel (co-volume) gas, p (v − b) = (γ − 1) e, v = 1/ρ
//! (Toro, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, 3rd
//! ed., 2009, §4.7, "the covolume gas").
//!
//! In the variable w = v − b the gas is the ideal gas: e = p w/(γ − 1), so
//! the Hugoniot of a shock from (p_K, w_K) is the ideal-gas one in w,
//!
//! ```text
//! w*/w_K = [(γ − 1) p* + (γ + 1) p_K] / [(γ + 1) p* + (γ − 1) p_K],
//! ```
//!
//! with mass flux Q² = (p* − p_K)/(w_K − w*), and an isentrope is
//! p w^γ = const. The sound speed is a = √(γ p /(ρ (1 − bρ))) and along an
//! isentrope ∫ a dρ/ρ = 2 a (1 − bρ)/(γ − 1), so the generalized Riemann
//! invariants are u ± 2 a (1 − bρ)/(γ − 1). The wave functions are then
//! (Toro eqs 4.97–4.98)
//!
//! ```text
//! f_K(p) = (p − p_K) √(A_K/(p + B_K)),  A_K = 2 (1 − bρ_K)/((γ + 1) ρ_K),
//!                                        B_K = (γ − 1) p_K/(γ + 1)        (shock, p > p_K)
//! f_K(p) = 2 a_K (1 − bρ_K)/(γ − 1) [(p/p_K)^((γ − 1)/(2γ)) − 1]         (rarefaction)
//! ```
//!
//! and p* is the root of f_L + f_R + u_R − u_L, found by a Newton
//! iteration safeguarded by bisection. Inside a rarefaction fan the state
//! at ξ = x/t solves u ∓ a = ξ with the invariant and the isentrope, by
//! bisection in w. Vacuum is not handled (an error).

/// Relative tolerance of p*.
const TOLERANCE: f64 = 1e-14;

/// Iteration cap of the root finders.
const MAX_ITERATIONS: usize = 300;

/// A state (ρ, u, p).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    pub velocity: f64,
    /// Pressure, Pa.
    pub pressure: f64,
}

/// The Riemann problem: one gas (γ, b), the left and right states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiemannProblem {
    /// Ratio of specific heats γ.
    pub gamma: f64,
    /// Co-volume b, m³/kg.
    pub covolume: f64,
    /// State for x < x₀.
    pub left: State,
    /// State for x > x₀.
    pub right: State,
}

/// The solved problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiemannSolution {
    problem: RiemannProblem,
    p_star: f64,
    u_star: f64,
    /// w = v − b on either side of the contact.
    w_star: [f64; 2],
}

impl RiemannProblem {
    /// Sound speed a = √(γ p/(ρ (1 − bρ))).
    fn sound_speed(&self, s: &State) -> f64 {
        (self.gamma * s.pressure / (s.density * (1.0 - self.covolume * s.density))).sqrt()
    }

    /// w = 1/ρ − b.
    fn w(&self, s: &State) -> f64 {
        1.0 / s.density - self.covolume
    }

    /// f_K(p) and its derivative.
    fn wave_function(&self, p: f64, s: &State) -> (f64, f64) {
        let g = self.gamma;
        let b = self.covolume;
        if p > s.pressure {
            let a = 2.0 * (1.0 - b * s.density) / ((g + 1.0) * s.density);
            let bk = (g - 1.0) / (g + 1.0) * s.pressure;
            let q = (a / (p + bk)).sqrt();
            let f = (p - s.pressure) * q;
            (f, q * (1.0 - 0.5 * (p - s.pressure) / (p + bk)))
        } else {
            let ak = self.sound_speed(s);
            let c = 2.0 * ak * (1.0 - b * s.density) / (g - 1.0);
            let r = p / s.pressure;
            let e = (g - 1.0) / (2.0 * g);
            (c * (r.powf(e) - 1.0), c * e * r.powf(e - 1.0) / s.pressure)
        }
    }

    /// Solves for the star region.
    pub fn solve(&self) -> Result<RiemannSolution, String> {
        let (l, r) = (&self.left, &self.right);
        for s in [l, r] {
            if !(s.density > 0.0 && s.pressure > 0.0 && self.covolume * s.density < 1.0) {
                return Err(format!(
                    "state {s:?} is not a Noble–Abel gas state (b = {})",
                    self.covolume
                ));
            }
        }
        let du = r.velocity - l.velocity;
        let f = |p: f64| {
            let (fl, dl) = self.wave_function(p, l);
            let (fr, dr) = self.wave_function(p, r);
            (fl + fr + du, dl + dr)
        };
        // f rises with p; f(0⁺) < 0 unless vacuum forms.
        let mut lo = 1e-12 * l.pressure.min(r.pressure);
        if f(lo).0 >= 0.0 {
            return Err("the data create a vacuum".into());
        }
        let mut hi = l.pressure.max(r.pressure);
        while f(hi).0 < 0.0 {
            hi *= 2.0;
        }
        let mut p = 0.5 * (lo + hi);
        for _ in 0..MAX_ITERATIONS {
            let (v, d) = f(p);
            if v < 0.0 {
                lo = p;
            } else {
                hi = p;
            }
            let newton = p - v / d;
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - p).abs() <= TOLERANCE * next {
                p = next;
                break;
            }
            p = next;
        }
        let (fl, _) = self.wave_function(p, l);
        let (fr, _) = self.wave_function(p, r);
        let u = 0.5 * (l.velocity + r.velocity) + 0.5 * (fr - fl);
        let w_star = [l, r].map(|s| {
            let w = self.w(s);
            let g = self.gamma;
            if p > s.pressure {
                w * ((g - 1.0) * p + (g + 1.0) * s.pressure)
                    / ((g + 1.0) * p + (g - 1.0) * s.pressure)
            } else {
                w * (s.pressure / p).powf(1.0 / g)
            }
        });
        Ok(RiemannSolution {
            problem: *self,
            p_star: p,
            u_star: u,
            w_star,
        })
    }
}

impl RiemannSolution {
    /// Star pressure, Pa.
    pub fn p_star(&self) -> f64 {
        self.p_star
    }

    /// Star velocity (the contact's), m/s.
    pub fn u_star(&self) -> f64 {
        self.u_star
    }

    /// Star densities left and right of the contact, kg/m³.
    pub fn rho_star(&self) -> [f64; 2] {
        self.w_star.map(|w| 1.0 / (w + self.problem.covolume))
    }

    /// The speed of the shock on side `k` (0 left, 1 right), if that wave
    /// is a shock: u_K ∓ Q/ρ_K.
    pub fn shock_speed(&self, k: usize) -> Option<f64> {
        let pr = &self.problem;
        let s = if k == 0 { &pr.left } else { &pr.right };
        if self.p_star <= s.pressure {
            return None;
        }
        let q = ((self.p_star - s.pressure) / (pr.w(s) - self.w_star[k])).sqrt();
        Some(if k == 0 {
            s.velocity - q / s.density
        } else {
            s.velocity + q / s.density
        })
    }

    /// The state in a rarefaction fan of side `k` at ξ: u ∓ a = ξ with
    /// u ± 2a(1 − bρ)/(γ − 1) and p w^γ constant from the side's state.
    fn fan(&self, k: usize, xi: f64) -> State {
        let pr = &self.problem;
        let s = if k == 0 { &pr.left } else { &pr.right };
        let (g, b) = (pr.gamma, pr.covolume);
        let sign = if k == 0 { 1.0 } else { -1.0 };
        let w0 = pr.w(s);
        let entropy = s.pressure * w0.powf(g);
        let invariant =
            s.velocity + sign * 2.0 * pr.sound_speed(s) * (1.0 - b * s.density) / (g - 1.0);
        let state = |w: f64| {
            let rho = 1.0 / (w + b);
            let p = entropy / w.powf(g);
            let a = (g * p / (rho * (1.0 - b * rho))).sqrt();
            let u = invariant - sign * 2.0 * a * (1.0 - b * rho) / (g - 1.0);
            (
                State {
                    density: rho,
                    velocity: u,
                    pressure: p,
                },
                u - sign * a - xi,
            )
        };
        // u ∓ a − ξ runs from (head) to (tail) as w goes from w₀ to w*;
        // bisection on w.
        let (mut lo, mut hi) = (w0, self.w_star[k]);
        let f_lo = state(lo).1;
        for _ in 0..MAX_ITERATIONS {
            let mid = 0.5 * (lo + hi);
            if (state(mid).1 > 0.0) == (f_lo > 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
            if (hi - lo).abs() <= 1e-15 * hi.abs() {
                break;
            }
        }
        state(0.5 * (lo + hi)).0
    }

    /// The state at ξ = (x − x₀)/t.
    pub fn sample(&self, xi: f64) -> State {
        let pr = &self.problem;
        let k = usize::from(xi > self.u_star);
        let (s, sign) = if k == 0 {
            (&pr.left, -1.0)
        } else {
            (&pr.right, 1.0)
        };
        let star = State {
            density: self.rho_star()[k],
            velocity: self.u_star,
            pressure: self.p_star,
        };
        // sign · ξ grows away from the contact on either side.
        if let Some(speed) = self.shock_speed(k) {
            return if sign * xi > sign * speed { *s } else { star };
        }
        let head = s.velocity + sign * pr.sound_speed(s);
        let tail = self.u_star + sign * pr.sound_speed(&star);
        if sign * xi >= sign * head {
            *s
        } else if sign * xi <= sign * tail {
            star
        } else {
            self.fan(k, xi)
        }
    }

    /// The mean of density, momentum and pressure over [a, b] at time t
    /// (x₀ the diaphragm), by the midpoint rule on `n` sub-cells: the
    /// density as (ρ, u, p) of those means, u = ⟨ρu⟩/⟨ρ⟩.
    pub fn cell_average(&self, a: f64, b: f64, x0: f64, t: f64, n: usize) -> State {
        let (mut rho, mut mom, mut p) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let x = a + (i as f64 + 0.5) * (b - a) / n as f64;
            let s = self.sample((x - x0) / t);
            rho += s.density;
            mom += s.density * s.velocity;
            p += s.pressure;
        }
        State {
            density: rho / n as f64,
            velocity: mom / rho,
            pressure: p / n as f64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(covolume: f64) -> RiemannProblem {
        RiemannProblem {
            gamma: 1.4,
            covolume,
            left: State {
                density: 1.0,
                velocity: 0.0,
                pressure: 1.0,
            },
            right: State {
                density: 0.125,
                velocity: 0.0,
                pressure: 0.1,
            },
        }
    }

    /// With b = 0 the gas is ideal: Sod's problem has p* = 0.30313 and
    /// u* = 0.92745 (Toro Table 4.2, test 1).
    #[test]
    fn without_covolume_it_is_sods_problem() {
        let s = problem(0.0).solve().unwrap();
        assert!((s.p_star() - 0.30313).abs() < 5e-6, "{}", s.p_star());
        assert!((s.u_star() - 0.92745).abs() < 5e-6, "{}", s.u_star());
        let [l, r] = s.rho_star();
        assert!((l - 0.42632).abs() < 5e-6 && (r - 0.26557).abs() < 5e-6);
    }

    /// Across the computed shock, mass, momentum and energy fluxes are the
    /// same in the shock's frame (e = p (v − b)/(γ − 1)), to round-off;
    /// across the fan the left invariant and the isentrope hold.
    #[test]
    fn with_covolume_the_shock_and_the_fan_satisfy_their_conditions() {
        let pr = problem(0.5);
        let s = pr.solve().unwrap();
        let speed = s.shock_speed(1).expect("a right shock");
        let (g, b) = (pr.gamma, pr.covolume);
        let flux = |st: &State| {
            let v = st.velocity - speed;
            let e = st.pressure * (1.0 / st.density - b) / (g - 1.0);
            let h = e + st.pressure / st.density + 0.5 * v * v;
            [
                st.density * v,
                st.density * v * v + st.pressure,
                st.density * v * h,
            ]
        };
        let star = State {
            density: s.rho_star()[1],
            velocity: s.u_star(),
            pressure: s.p_star(),
        };
        let (a, c) = (flux(&pr.right), flux(&star));
        for k in 0..3 {
            assert!(
                (a[k] - c[k]).abs() <= 1e-12 * a[k].abs().max(1.0),
                "{k}: {a:?} {c:?}"
            );
        }
        // Inside the left fan: the invariant u + 2a(1 − bρ)/(γ − 1) and
        // p (v − b)^γ of the left state, and u − a = ξ.
        let a_l = pr.sound_speed(&pr.left);
        let j = 2.0 * a_l * (1.0 - b) / (g - 1.0);
        let k0 = pr.left.pressure * (1.0 - b).powf(g);
        let head = -a_l;
        let tail = s.u_star()
            - pr.sound_speed(&State {
                density: s.rho_star()[0],
                velocity: s.u_star(),
                pressure: s.p_star(),
            });
        for f in [0.1, 0.5, 0.9] {
            let xi = head + f * (tail - head);
            let st = s.sample(xi);
            let a = pr.sound_speed(&st);
            assert!((st.velocity + 2.0 * a * (1.0 - b * st.density) / (g - 1.0) - j).abs() < 1e-10);
            assert!((st.pressure * (1.0 / st.density - b).powf(g) / k0 - 1.0).abs() < 1e-10);
            assert!((st.velocity - a - xi).abs() < 1e-10, "{st:?} at {xi}");
        }
        // The fan joins the left state at its head and the star at its tail.
        assert!((s.sample(head + 1e-12).density - 1.0).abs() < 1e-6);
        assert!((s.sample(tail - 1e-12).density - s.rho_star()[0]).abs() < 1e-6);
    }

    #[test]
    fn non_gas_states_and_vacuum_are_refused() {
        let mut pr = problem(0.5);
        pr.left.density = 2.0; // bρ = 1
        assert!(pr.solve().is_err());
        let mut pr = problem(0.0);
        pr.left.velocity = -20.0;
        pr.right.velocity = 20.0;
        assert!(pr.solve().unwrap_err().contains("vacuum"));
    }
}
