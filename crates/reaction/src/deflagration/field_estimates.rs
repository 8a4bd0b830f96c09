//! The surface estimates that read the reactant's field, not only the
//! surface cells' normals ([`SurfaceArea::ExposedFaces`],
//! [`SurfaceArea::Gradient`], [`SurfaceArea::Upwind`]), for
//! [`surface_area_densities`].

use super::*;

/// [`surface_area_densities`] for [`SurfaceArea::ExposedFaces`]: every
/// surface cell of [`detect_surface`] (`outermost_in_column` off) gets
/// a/V = max(0, Σ_f (n·e_f) / h_f) over its faces f whose neighbour is
/// empty (A_f / V = 1 / h_f along the face's axis).
pub(super) fn exposed_face_densities(
    grid: &CellGrid,
    reactant: &[f64],
    options: &SurfaceDetection,
    work: &mut SurfaceWork,
    out: &mut [f64],
) -> Result<usize, DeflagrationError> {
    let every = SurfaceDetection {
        outermost_in_column: false,
        ..*options
    };
    let [nx, ny, nz] = &mut work.normal;
    let count = detect_surface(grid, reactant, &every, &mut work.on_surface, [nx, ny, nz])?;
    let field = Field { grid, reactant };
    let threshold = options.present_threshold;
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let c = grid.index(i, j, k);
                if !work.on_surface[c] {
                    out[c] = 0.0;
                    continue;
                }
                let at = [i as isize, j as isize, k as isize];
                let mut flux = 0.0;
                for axis in 0..3 {
                    for s in [1_isize, -1] {
                        if field.neighbour(at, axis, s).is_some_and(|v| v <= threshold) {
                            flux += s as f64 * work.normal[axis][c] / grid.spacing[axis];
                        }
                    }
                }
                out[c] = flux.max(0.0);
            }
        }
    }
    Ok(count)
}

/// [`surface_area_densities`] for [`SurfaceArea::Gradient`]: the surface
/// cells and normals of [`detect_surface`] (with `options`), then every
/// cell's |∇φ| (`options.stencil`) times its volume over the gathering
/// cell's added to the a/V of the surface cell that its column meets.
/// The column runs along the axis k of largest h_k |n_k| of the cell's
/// own normal n = −∇φ/|∇φ|: outward (the side n points to) from a cell
/// holding reactant, up to the first surface cell, stopping at an empty
/// cell; inward from an empty cell, up to the first cell holding
/// reactant, which must be a surface cell; either within
/// [`GATHER_DEPTH`] cells. A gradient whose column meets no surface cell
/// is not counted. Each surface cell's sum is then divided by the span
/// φ_peak − φ_low of the reactant along the surface cell's own normal
/// (the cells nearest the line through its centre, one a step along the
/// normal's dominant axis): the largest φ inward and the smallest outward
/// within [`SPAN_DEPTH`] steps, itself included, clamped to [0, 1]. By
/// the coarea formula the sum is ∫ A(s) ds over the levels s between
/// them, so the quotient is the mean area of the level sets that exist.
/// A front from empty (φ = 0) to a full cell (φ = 1) keeps its sum; a
/// layer thinner than its projected profile (a particle block burnt down
/// to a few cells, whose two faces' profiles overlap below φ = 1) keeps the area of its faces instead of shrinking with its peak,
/// and a front into a trace of the reactant (a particle reactant's floor
/// outside the particles) counts the trace's level sets too.
pub(super) fn gradient_densities(
    grid: &CellGrid,
    reactant: &[f64],
    options: &SurfaceDetection,
    work: &mut SurfaceWork,
    out: &mut [f64],
) -> Result<usize, DeflagrationError> {
    if let Some(r) = options.ring_inner_radius {
        if !(r >= 0.0 && r.is_finite()) {
            return invalid("ring_inner_radius", r, "a finite value ≥ 0 (m)");
        }
    }
    let [nx, ny, nz] = &mut work.normal;
    let count = detect_surface(grid, reactant, options, &mut work.on_surface, [nx, ny, nz])?;
    out.fill(0.0);
    let field = Field { grid, reactant };
    let threshold = options.present_threshold;
    // A ring's volume is proportional to its centre radius.
    let weight = |i: usize| match options.ring_inner_radius {
        Some(r0) => r0 + (i as f64 + 0.5) * grid.spacing[0],
        None => 1.0,
    };
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let at = [i as isize, j as isize, k as isize];
                let g = field.gradient(at, options.stencil);
                let size = norm(g);
                if !(size > 0.0) {
                    continue;
                }
                // The column's axis and the side the normal −g points to.
                let mut axis = 0;
                for a in 1..3 {
                    if grid.spacing[a] * g[a].abs() > grid.spacing[axis] * g[axis].abs() {
                        axis = a;
                    }
                }
                let outward: isize = if g[axis] <= 0.0 { 1 } else { -1 };
                let holds = reactant[grid.index(i, j, k)] > threshold;
                let step = if holds { outward } else { -outward };
                let mut p = at;
                let mut gatherer = None;
                for _ in 0..=GATHER_DEPTH {
                    let c = grid.index(p[0] as usize, p[1] as usize, p[2] as usize);
                    let present = reactant[c] > threshold;
                    if work.on_surface[c] {
                        gatherer = Some((c, p[0] as usize));
                        break;
                    }
                    if holds != present {
                        // Outward into an empty cell, or inward onto
                        // reactant that is not a surface cell.
                        break;
                    }
                    p[axis] += step;
                    if p[axis] < 0 || p[axis] as usize >= grid.n[axis] {
                        break;
                    }
                }
                if let Some((c, i_gather)) = gatherer {
                    out[c] += size * weight(i) / weight(i_gather);
                }
            }
        }
    }
    // Each surface cell's span: the largest φ inward along its own normal
    // and the smallest outward, within SPAN_DEPTH cells.
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let c = grid.index(i, j, k);
                if !(work.on_surface[c] && out[c] > 0.0) {
                    continue;
                }
                // Along the normal, one cell a step on its dominant axis.
                let n = [work.normal[0][c], work.normal[1][c], work.normal[2][c]];
                let d = [0, 1, 2].map(|a| n[a] / grid.spacing[a]);
                let m = d[0].abs().max(d[1].abs()).max(d[2].abs());
                if !(m > 0.0) {
                    continue;
                }
                let e = d.map(|x| x / m);
                let at = [i as f64, j as f64, k as f64];
                let (mut top, mut bottom) = (reactant[c], reactant[c]);
                for side in [-1.0, 1.0] {
                    for t in 1..=SPAN_DEPTH {
                        let q = [0, 1, 2].map(|a| (at[a] + side * t as f64 * e[a]).round());
                        if (0..3).any(|a| q[a] < 0.0 || q[a] >= grid.n[a] as f64) {
                            break;
                        }
                        let phi = reactant[grid.index(q[0] as usize, q[1] as usize, q[2] as usize)];
                        if side > 0.0 {
                            bottom = bottom.min(phi);
                        } else {
                            top = top.max(phi);
                        }
                    }
                }
                let span = top.min(1.0) - bottom.max(0.0);
                if span > 0.0 {
                    out[c] /= span;
                }
            }
        }
    }
    Ok(count)
}

/// The reactant's surface by the upwind estimate ([`SurfaceArea::Upwind`]):
/// a/V in every cell of `grid` (1/m), the cells where it is > 0 flagged in
/// `on_surface` with their unit outward normals; returns their number.
///
/// In a cell holding reactant (φ > `options.present_threshold`) with a
/// non-zero gradient of `options.stencil` or an empty face neighbour, the
/// normal is n = −∇φ/|∇φ| (as [`detect_surface`] gives it) and
/// a/V = Σ_k |n_k| J_k / h_k with J_k = max(0, φ − φ_k), φ_k the face
/// neighbour on the side n points to along k (0 where it is at or below
/// the threshold; no drop toward a grid edge, which is neither a surface
/// nor an empty neighbour). `reactant` is a volume fraction (a full cell
/// 1). Unlike [`detect_surface`], a cell behind a partly burnt one (its
/// neighbour still holds reactant) is on the surface for the drop it
/// holds: the front's area is shared between the cells its jump spans.
/// `options.outermost_in_column` plays no part.
pub fn upwind_area_densities(
    grid: &CellGrid,
    reactant: &[f64],
    options: &SurfaceDetection,
    on_surface: &mut [bool],
    normal: [&mut [f64]; 3],
    out: &mut [f64],
) -> Result<usize, DeflagrationError> {
    same_lengths(
        grid,
        &[
            ("reactant", reactant.len()),
            ("on_surface", on_surface.len()),
            ("normal[0]", normal[0].len()),
            ("normal[1]", normal[1].len()),
            ("normal[2]", normal[2].len()),
            ("out", out.len()),
        ],
    )?;
    check_grid(grid, options)?;
    let [nx_out, ny_out, nz_out] = normal;
    let threshold = options.present_threshold;
    let field = Field { grid, reactant };
    let mut count = 0;
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let c = grid.index(i, j, k);
                let at = [i as isize, j as isize, k as isize];
                let phi = reactant[c];
                let mut density = 0.0;
                let mut unit = [0.0; 3];
                // A drop needs a lower face neighbour: without one (the
                // reactant's interior) the cell holds no surface, and its
                // gradient is not computed.
                let lower = (0..3).any(|axis| {
                    [1, -1].into_iter().any(|s| {
                        field
                            .neighbour(at, axis, s)
                            .is_some_and(|v| (if v > threshold { v } else { 0.0 }) < phi)
                    })
                });
                if phi > threshold && lower {
                    let g = field.gradient(at, options.stencil);
                    let empty = field.empty_neighbours(at, threshold);
                    if norm(g) > 0.0 || empty.is_some() {
                        unit = outward_normal(g, empty);
                        for (axis, &n) in unit.iter().enumerate() {
                            if n == 0.0 {
                                continue;
                            }
                            let s = if n > 0.0 { 1 } else { -1 };
                            let Some(next) = field.neighbour(at, axis, s) else {
                                continue;
                            };
                            let next = if next > threshold { next } else { 0.0 };
                            density += n.abs() * (phi - next).max(0.0) / grid.spacing[axis];
                        }
                    }
                }
                let surface = density > 0.0;
                on_surface[c] = surface;
                out[c] = density;
                let unit = if surface { unit } else { [0.0; 3] };
                nx_out[c] = unit[0];
                ny_out[c] = unit[1];
                nz_out[c] = unit[2];
                count += usize::from(surface);
            }
        }
    }
    Ok(count)
}
