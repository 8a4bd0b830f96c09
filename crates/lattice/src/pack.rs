//! Heterogeneous packs for the lattice (seed 003 §3.1 and §4.1): a
//! crystal/binder image with one node per pixel, or a random pack of
//! discs of one diameter at a given mass fraction, the material of each
//! node taken from the pixel or disc it falls in.
//!
//! The random pack (`docs/physics/lattice/packs.md`) stands in for RocPack
//! (seed 003 ref. 35), which grows particles in a periodic box
//! (Lubachevsky–Stillinger). Here the N = round(φ W H / (π R²)) discs are
//! placed in a periodic box (as RocPack's) by random sequential addition
//! (up to 200 tries each, the last try kept if all overlap) and then
//! relaxed: every overlapping pair is pushed apart along its centre line by
//! half the overlap (plus 1 %) each, a Jacobi sweep over all pairs, until
//! no pair overlaps. Random sequential addition alone jams near φ ≈ 0.55 in 2D; the
//! relaxation reaches the 0.65 area fraction of 80 wt % AP in HTPB. All
//! random numbers come from a SplitMix64 stream of the seed, so a pack is
//! the same bits for a seed on every machine.

use super::geometry::{Dim, Geometry};
use super::model::MsdmLattice;

/// A grey-level image, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct GrayImage {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Largest grey level (the PGM maxval).
    pub max_value: u16,
    /// Grey levels, row-major from the top row.
    pub pixels: Vec<u16>,
}

impl GrayImage {
    /// Grey level of the pixel over lattice node (ix, iy), iy counted from
    /// the bottom row of the image (the lattice's y points up).
    #[inline]
    pub fn at_lattice(&self, ix: usize, iy: usize) -> u16 {
        self.pixels[(self.height - 1 - iy) * self.width + ix]
    }
}

/// Reads a binary (`P5`) or plain (`P2`) PGM image, with `#` comments in
/// the header.
pub fn read_pgm(bytes: &[u8]) -> Result<GrayImage, String> {
    let mut pos = 0usize;
    // Next header token, skipping whitespace and comments.
    let token = |pos: &mut usize| -> Result<String, String> {
        loop {
            while *pos < bytes.len() && bytes[*pos].is_ascii_whitespace() {
                *pos += 1;
            }
            if *pos < bytes.len() && bytes[*pos] == b'#' {
                while *pos < bytes.len() && bytes[*pos] != b'\n' {
                    *pos += 1;
                }
            } else {
                break;
            }
        }
        let start = *pos;
        while *pos < bytes.len() && !bytes[*pos].is_ascii_whitespace() && bytes[*pos] != b'#' {
            *pos += 1;
        }
        if start == *pos {
            return Err("PGM: the header ends early".into());
        }
        Ok(String::from_utf8_lossy(&bytes[start..*pos]).into_owned())
    };
    let magic = token(&mut pos)?;
    if magic != "P5" && magic != "P2" {
        return Err(format!(
            "PGM: magic number `{magic}`, expected `P5` (binary) or `P2` (plain)"
        ));
    }
    let number = |what: &str, pos: &mut usize| -> Result<usize, String> {
        let t = token(pos)?;
        t.parse::<usize>()
            .map_err(|_| format!("PGM: {what} `{t}` is not a non-negative integer"))
    };
    let width = number("width", &mut pos)?;
    let height = number("height", &mut pos)?;
    let max = number("maxval", &mut pos)?;
    if width == 0 || height == 0 {
        return Err(format!("PGM: the image is {width} × {height} pixels"));
    }
    if max == 0 || max > 65535 {
        return Err(format!("PGM: maxval {max}, expected 1 to 65535"));
    }
    let count = width
        .checked_mul(height)
        .ok_or_else(|| format!("PGM: {width} × {height} pixels overflow"))?;
    let mut pixels = Vec::with_capacity(count);
    if magic == "P5" {
        // Exactly one whitespace byte after maxval.
        pos += 1;
        let wide = max > 255;
        let need = count * if wide { 2 } else { 1 };
        if bytes.len() < pos + need {
            return Err(format!(
                "PGM: {} bytes of pixel data, expected {need}",
                bytes.len().saturating_sub(pos)
            ));
        }
        let data = &bytes[pos..pos + need];
        if wide {
            pixels.extend(
                data.chunks_exact(2)
                    .map(|c| u16::from_be_bytes([c[0], c[1]])),
            );
        } else {
            pixels.extend(data.iter().map(|&b| u16::from(b)));
        }
    } else {
        for k in 0..count {
            let v = number("pixel", &mut pos).map_err(|e| format!("{e} (pixel {k})"))?;
            pixels.push(v as u16);
        }
    }
    if let Some((k, v)) = pixels
        .iter()
        .enumerate()
        .find(|(_, &v)| usize::from(v) > max)
    {
        return Err(format!("PGM: pixel {k} has level {v} above maxval {max}"));
    }
    Ok(GrayImage {
        width,
        height,
        max_value: max as u16,
        pixels,
    })
}

/// The eight bytes every PNG file starts with.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

/// Reads a PNG image as grey levels (the `png` crate's decoder): grey
/// images of 1, 2, 4, 8 or 16 bits and palette images are expanded to 8
/// (or 16) bits; an alpha channel is ignored; colour pixels become their
/// Rec. 601 luma, round((299 R + 587 G + 114 B)/1000), so a grey image
/// saved as RGB keeps its levels. `max_value` is 255, or 65535 for 16-bit
/// images. The first frame of an animated PNG is read.
pub fn read_png(bytes: &[u8]) -> Result<GrayImage, String> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("PNG: cannot read the header: {e}"))?;
    let mut buf = vec![0u8; reader.output_buffer_size()];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| format!("PNG: cannot decode the pixels: {e}"))?;
    let (width, height) = (info.width as usize, info.height as usize);
    if width == 0 || height == 0 {
        return Err(format!("PNG: the image is {width} × {height} pixels"));
    }
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => {
            return Err("PNG: a palette image was not expanded to colour".into());
        }
    };
    let wide = match info.bit_depth {
        png::BitDepth::Eight => false,
        png::BitDepth::Sixteen => true,
        d => return Err(format!("PNG: bit depth {d:?} was not expanded to 8 bits")),
    };
    let bytes_per_sample = if wide { 2 } else { 1 };
    let sample = |row: &[u8], k: usize| -> u32 {
        if wide {
            u32::from(u16::from_be_bytes([row[2 * k], row[2 * k + 1]]))
        } else {
            u32::from(row[k])
        }
    };
    let mut pixels = Vec::with_capacity(width * height);
    for row in buf[..info.buffer_size()].chunks_exact(info.line_size) {
        let row = &row[..width * channels * bytes_per_sample];
        for x in 0..width {
            let k = x * channels;
            let level = if channels >= 3 {
                let (r, g, b) = (sample(row, k), sample(row, k + 1), sample(row, k + 2));
                (299 * r + 587 * g + 114 * b + 500) / 1000
            } else {
                sample(row, k)
            };
            pixels.push(level as u16);
        }
    }
    Ok(GrayImage {
        width,
        height,
        max_value: if wide { u16::MAX } else { 255 },
        pixels,
    })
}

/// Reads a crystal/binder image, PNG (recognised by its signature) or PGM
/// (`P5`/`P2`, see [`read_pgm`]).
pub fn read_image(bytes: &[u8]) -> Result<GrayImage, String> {
    if bytes.starts_with(&PNG_SIGNATURE) {
        read_png(bytes)
    } else {
        read_pgm(bytes)
    }
}

/// Reads the crystal/binder image file `path` (PNG or PGM, see
/// [`read_image`]); every error names the file.
pub fn read_image_file(path: &std::path::Path) -> Result<GrayImage, String> {
    let bytes =
        std::fs::read(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    read_image(&bytes).map_err(|e| format!("`{}`: {e}", path.display()))
}

/// A 2D lattice with one node per pixel: material `crystal` where the
/// grey level is at least `threshold`, `binder` elsewhere.
pub fn image_geometry(
    img: &GrayImage,
    spacing: f64,
    threshold: u16,
    crystal: u16,
    binder: u16,
    diagonals: bool,
) -> Geometry {
    Geometry::new(
        Dim::Two,
        [img.width, img.height, 1],
        spacing,
        diagonals,
        |ix, iy, _| {
            Some(if img.at_lattice(ix, iy) >= threshold {
                crystal
            } else {
                binder
            })
        },
    )
}

/// Area (2D) fraction of particles of density `rho_particle` that make the
/// mass fraction `mass_fraction` in a binder of density `rho_binder`.
pub fn area_fraction(mass_fraction: f64, rho_particle: f64, rho_binder: f64) -> f64 {
    let vp = mass_fraction / rho_particle;
    let vb = (1.0 - mass_fraction) / rho_binder;
    vp / (vp + vb)
}

/// Mass fraction of material `m` over the solid nodes of a lattice.
pub fn node_mass_fraction(lat: &MsdmLattice, m: usize) -> f64 {
    let n = lat.len();
    let total: f64 = lat.mass.iter().sum();
    let part: f64 = lat.mass_k[m * n..(m + 1) * n].iter().sum();
    part / total
}

/// SplitMix64 (Steele, Lea & Flood 2014): a small, fast stream with good
/// statistics, the same bits on every platform.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// The stream of `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A pack of equal discs in the box [0, W] × [0, H].
#[derive(Debug, Clone, PartialEq)]
pub struct DiscPack {
    /// Box width W, m.
    pub width: f64,
    /// Box height H, m.
    pub height: f64,
    /// Disc diameter D, m.
    pub diameter: f64,
    /// Disc centres, m.
    pub centres: Vec<[f64; 2]>,
    /// Relaxation sweeps it took to remove the overlaps.
    pub sweeps: usize,
}

/// Uniform periodic bins of edge ≥ D over the box: disc k is in bin
/// `cell(c_k)`. With fewer than 3 bins along an axis every disc is a
/// candidate neighbour.
struct Bins {
    nx: usize,
    ny: usize,
    ex: f64,
    ey: f64,
    start: Vec<usize>,
    items: Vec<usize>,
    next: Vec<usize>,
}

impl Bins {
    fn new(width: f64, height: f64, edge: f64) -> Self {
        let nx = ((width / edge).floor() as usize).max(1);
        let ny = ((height / edge).floor() as usize).max(1);
        Self {
            nx,
            ny,
            ex: width / nx as f64,
            ey: height / ny as f64,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
            next: Vec::new(),
        }
    }

    fn cell(&self, p: [f64; 2]) -> (usize, usize) {
        let cx = ((p[0] / self.ex).floor().max(0.0) as usize).min(self.nx - 1);
        let cy = ((p[1] / self.ey).floor().max(0.0) as usize).min(self.ny - 1);
        (cx, cy)
    }

    /// Counting sort of the centres into the bins.
    fn fill(&mut self, centres: &[[f64; 2]]) {
        self.start.iter_mut().for_each(|s| *s = 0);
        for c in centres {
            let (cx, cy) = self.cell(*c);
            self.start[cx + self.nx * cy + 1] += 1;
        }
        for k in 1..self.start.len() {
            self.start[k] += self.start[k - 1];
        }
        self.items.clear();
        self.items.resize(centres.len(), 0);
        self.next.clear();
        self.next.extend_from_slice(&self.start);
        for (k, c) in centres.iter().enumerate() {
            let (cx, cy) = self.cell(*c);
            let b = cx + self.nx * cy;
            self.items[self.next[b]] = k;
            self.next[b] += 1;
        }
    }

    /// Calls `f(k)` once for every disc in the 3 × 3 bins around `p`
    /// (periodic), or for every disc when the bins are too few.
    fn around(&self, p: [f64; 2], mut f: impl FnMut(usize)) {
        if self.nx < 3 || self.ny < 3 {
            self.items.iter().for_each(|&k| f(k));
            return;
        }
        let (cx, cy) = self.cell(p);
        for dy in [self.ny - 1, 0, 1] {
            for dx in [self.nx - 1, 0, 1] {
                let b = (cx + dx) % self.nx + self.nx * ((cy + dy) % self.ny);
                for &k in &self.items[self.start[b]..self.start[b + 1]] {
                    f(k);
                }
            }
        }
    }
}

/// Minimum-image separation a − b in the periodic box.
#[inline]
fn separation(a: [f64; 2], b: [f64; 2], width: f64, height: f64) -> [f64; 2] {
    let mut dx = a[0] - b[0];
    let mut dy = a[1] - b[1];
    dx -= width * (dx / width).round();
    dy -= height * (dy / height).round();
    [dx, dy]
}

/// Largest relaxation sweeps before [`random_disc_pack`] gives up.
const MAX_SWEEPS: usize = 20_000;

/// A random pack of discs of diameter `diameter` covering the area fraction
/// `fraction` of the periodic box [0, `width`) × [0, `height`), no two
/// discs overlapping (see the module documentation). Errors name the
/// argument.
pub fn random_disc_pack(
    width: f64,
    height: f64,
    diameter: f64,
    fraction: f64,
    seed: u64,
) -> Result<DiscPack, String> {
    if !(diameter > 0.0 && diameter.is_finite()) {
        return Err(format!(
            "pack: field `diameter` = {diameter}, expected a finite value > 0"
        ));
    }
    if !(width > diameter && height > diameter && width.is_finite() && height.is_finite()) {
        return Err(format!(
            "pack: the box {width} × {height} m must be wider and taller than the diameter {diameter} m"
        ));
    }
    if !(fraction > 0.0 && fraction <= 0.8) {
        return Err(format!(
            "pack: area fraction {fraction} (from field `mass_fraction`), expected a value in (0, 0.8]"
        ));
    }
    let count = (fraction * width * height / (0.25 * std::f64::consts::PI * diameter * diameter))
        .round() as usize;
    if count == 0 {
        return Err(format!(
            "pack: area fraction {fraction} of a {width} × {height} m box holds no disc of diameter {diameter} m"
        ));
    }
    let mut rng = SplitMix64::new(seed);
    let mut bins = Bins::new(width, height, diameter);
    let mut centres: Vec<[f64; 2]> = Vec::with_capacity(count);
    let draw = |rng: &mut SplitMix64| [width * rng.uniform(), height * rng.uniform()];
    let d2 = diameter * diameter;
    // Random sequential addition; the bins are refilled after each disc
    // (counting sort, O(N) per disc: fine for the thousands of discs of
    // a mesoscale pack).
    for _ in 0..count {
        let mut candidate = draw(&mut rng);
        for _ in 0..200 {
            let mut free = true;
            bins.around(candidate, |k| {
                let [dx, dy] = separation(centres[k], candidate, width, height);
                free &= dx * dx + dy * dy >= d2;
            });
            if free {
                break;
            }
            candidate = draw(&mut rng);
        }
        centres.push(candidate);
        bins.fill(&centres);
    }
    // Relaxation: Gauss–Seidel sweeps over the overlapping pairs in disc
    // order, each pair set apart to D (1 + 10⁻⁶) at once.
    let target = diameter * (1.0 + 1e-6);
    let mut sweeps = 0;
    let mut near = Vec::new();
    loop {
        bins.fill(&centres);
        let mut overlapping = false;
        for k in 0..count {
            // Neighbours from the bins of the sweep's start: a disc that
            // moved out of its bin is caught by the next sweep, and the
            // last sweep moves nothing.
            near.clear();
            bins.around(centres[k], |j| {
                if j > k {
                    near.push(j);
                }
            });
            for &j in &near {
                let [dx, dy] = separation(centres[k], centres[j], width, height);
                let dist2 = dx * dx + dy * dy;
                if dist2 >= d2 {
                    continue;
                }
                overlapping = true;
                let dist = dist2.sqrt();
                // Coincident centres split along a direction set by the
                // pair.
                let (ux, uy) = if dist > 1e-12 * diameter {
                    (dx / dist, dy / dist)
                } else {
                    let a = (k * 7919 + j) as f64;
                    (a.cos(), a.sin())
                };
                let push = 0.5 * (target - dist);
                let ck = &mut centres[k];
                ck[0] = (ck[0] + push * ux).rem_euclid(width);
                ck[1] = (ck[1] + push * uy).rem_euclid(height);
                let cj = &mut centres[j];
                cj[0] = (cj[0] - push * ux).rem_euclid(width);
                cj[1] = (cj[1] - push * uy).rem_euclid(height);
            }
        }
        if !overlapping {
            break;
        }
        if sweeps == MAX_SWEEPS {
            return Err(format!(
                "pack: discs of diameter {diameter} m still overlap after {MAX_SWEEPS} relaxation sweeps at area fraction {fraction}; lower field `mass_fraction` or enlarge the box"
            ));
        }
        sweeps += 1;
    }
    Ok(DiscPack {
        width,
        height,
        diameter,
        centres,
        sweeps,
    })
}

impl DiscPack {
    /// Area fraction of the discs, N π R² / (W H).
    pub fn area_fraction(&self) -> f64 {
        let r = 0.5 * self.diameter;
        self.centres.len() as f64 * std::f64::consts::PI * r * r / (self.width * self.height)
    }

    /// Smallest periodic distance between two centres over D (≥ 1 without
    /// overlap; ∞ for fewer than two discs).
    pub fn closest_pair(&self) -> f64 {
        let mut best = f64::INFINITY;
        for (k, a) in self.centres.iter().enumerate() {
            for b in &self.centres[k + 1..] {
                let [dx, dy] = separation(*a, *b, self.width, self.height);
                best = best.min((dx * dx + dy * dy).sqrt());
            }
        }
        best / self.diameter
    }

    /// Per node of an `nx` × `ny` lattice of spacing `spacing` (node (ix,
    /// iy) at (ix h, iy h), the box repeated periodically): whether it lies
    /// inside a disc, row-major from the bottom row.
    pub fn rasterise(&self, nx: usize, ny: usize, spacing: f64) -> Vec<bool> {
        let mut bins = Bins::new(self.width, self.height, self.diameter);
        bins.fill(&self.centres);
        let r2 = 0.25 * self.diameter * self.diameter;
        let mut inside = vec![false; nx * ny];
        for iy in 0..ny {
            for ix in 0..nx {
                let p = [
                    (ix as f64 * spacing).rem_euclid(self.width),
                    (iy as f64 * spacing).rem_euclid(self.height),
                ];
                let mut hit = false;
                bins.around(p, |k| {
                    let [dx, dy] = separation(self.centres[k], p, self.width, self.height);
                    hit |= dx * dx + dy * dy <= r2;
                });
                inside[ix + nx * iy] = hit;
            }
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::super::cases::inert_eos;
    use super::super::law::LatticeMaterial;
    use super::super::model::{MsdmLattice, MsdmOptions};
    use super::*;

    #[test]
    fn plain_and_binary_pgm_read_with_comments() {
        let plain = b"P2\n# a 3 x 2 test\n3 2\n# levels\n255\n0 10 255\n7 8 9\n";
        let img = read_pgm(plain).unwrap();
        assert_eq!((img.width, img.height, img.max_value), (3, 2, 255));
        assert_eq!(img.pixels, vec![0, 10, 255, 7, 8, 9]);
        // Lattice row 0 is the bottom image row.
        assert_eq!(img.at_lattice(0, 0), 7);
        assert_eq!(img.at_lattice(2, 1), 255);
        let mut binary = b"P5 3 2 255\n".to_vec();
        binary.extend_from_slice(&[0, 10, 255, 7, 8, 9]);
        assert_eq!(read_pgm(&binary).unwrap(), img);
        let mut wide = b"P5 2 1 1000\n".to_vec();
        wide.extend_from_slice(&[0x03, 0xE8, 0x00, 0x05]);
        assert_eq!(read_pgm(&wide).unwrap().pixels, vec![1000, 5]);
    }

    /// A PNG of `width` × `height` pixels from the `png` crate's encoder.
    fn encode_png(
        width: u32,
        height: u32,
        color: png::ColorType,
        depth: png::BitDepth,
        data: &[u8],
    ) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, width, height);
            enc.set_color(color);
            enc.set_depth(depth);
            let mut w = enc.write_header().unwrap();
            w.write_image_data(data).unwrap();
        }
        out
    }

    #[test]
    fn png_reads_grey_wide_colour_and_low_bit_images() {
        use png::{BitDepth, ColorType};
        // 3 × 2 grey, row 0 on top.
        let grey = encode_png(
            3,
            2,
            ColorType::Grayscale,
            BitDepth::Eight,
            &[0, 128, 255, 7, 8, 9],
        );
        let img = read_png(&grey).unwrap();
        assert_eq!((img.width, img.height, img.max_value), (3, 2, 255));
        assert_eq!(img.pixels, vec![0, 128, 255, 7, 8, 9]);
        // The lattice's y points up: node (0, 0) is the bottom-left pixel.
        assert_eq!(img.at_lattice(0, 0), 7);
        assert_eq!(img.at_lattice(2, 1), 255);
        // The same image as PGM reads to the same pixels.
        let pgm = read_image(b"P2 3 2 255\n0 128 255\n7 8 9\n").unwrap();
        assert_eq!(read_image(&grey).unwrap(), pgm);
        // 16-bit big-endian samples.
        let wide = encode_png(
            2,
            1,
            ColorType::Grayscale,
            BitDepth::Sixteen,
            &[0x03, 0xe8, 0, 5],
        );
        let img = read_png(&wide).unwrap();
        assert_eq!((img.max_value, img.pixels.clone()), (65535, vec![1000, 5]));
        // RGB: grey stays grey, colour becomes its luma
        // (299·200 + 587·100 + 114·50 + 500)/1000 = 124.
        let rgb = encode_png(
            2,
            1,
            ColorType::Rgb,
            BitDepth::Eight,
            &[90, 90, 90, 200, 100, 50],
        );
        assert_eq!(read_png(&rgb).unwrap().pixels, vec![90, 124]);
        // Grey with alpha: the alpha is ignored.
        let ga = encode_png(
            2,
            1,
            ColorType::GrayscaleAlpha,
            BitDepth::Eight,
            &[10, 0, 20, 255],
        );
        assert_eq!(read_png(&ga).unwrap().pixels, vec![10, 20]);
        // 1-bit black/white (0b1010_0000: pixels 1, 0, 1) expands to 0/255.
        let bw = encode_png(3, 1, ColorType::Grayscale, BitDepth::One, &[0b1010_0000]);
        assert_eq!(read_png(&bw).unwrap().pixels, vec![255, 0, 255]);
    }

    #[test]
    fn png_pack_sets_the_materials_by_threshold() {
        // The 3 × 3 image of the PGM mass-fraction test as a PNG: one
        // crystal pixel in the middle.
        let png = encode_png(
            3,
            3,
            png::ColorType::Grayscale,
            png::BitDepth::Eight,
            &[0, 0, 0, 0, 200, 0, 0, 0, 0],
        );
        let img = read_image(&png).unwrap();
        let g = image_geometry(&img, 1.0, 128, 0, 1, false);
        let centre = g.solid_index(1, 1, 0);
        assert_eq!(g.kind[centre], super::super::geometry::NodeKind::Solid(0));
        let solid: Vec<_> = (0..g.len()).filter(|&i| g.is_solid(i)).collect();
        assert_eq!(solid.len(), 9);
        let crystal = solid
            .iter()
            .filter(|&&i| g.kind[i] == super::super::geometry::NodeKind::Solid(0))
            .count();
        assert_eq!(crystal, 1);
    }

    #[test]
    fn bad_png_and_missing_files_are_reported_with_their_name() {
        use png::{BitDepth, ColorType};
        let good = encode_png(2, 2, ColorType::Grayscale, BitDepth::Eight, &[1, 2, 3, 4]);
        // Truncated after the signature and part of the header.
        let err = read_image(&good[..12]).unwrap_err();
        assert!(err.starts_with("PNG: cannot read the header"), "{err}");
        // Pixel data cut short.
        let err = read_image(&good[..good.len() - 20]).unwrap_err();
        assert!(err.starts_with("PNG:"), "{err}");
        let dir = std::env::temp_dir().join(format!("brisance-pack-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bad = dir.join("crystals.png");
        std::fs::write(&bad, &good[..12]).unwrap();
        let err = read_image_file(&bad).unwrap_err();
        assert!(
            err.contains("crystals.png") && err.contains("PNG:"),
            "{err}"
        );
        let ok = dir.join("ok.png");
        std::fs::write(&ok, &good).unwrap();
        assert_eq!(read_image_file(&ok).unwrap().pixels, vec![1, 2, 3, 4]);
        let missing = dir.join("missing.png");
        let err = read_image_file(&missing).unwrap_err();
        assert!(
            err.contains("cannot read") && err.contains("missing.png"),
            "{err}"
        );
        // A PGM through the same entry point, its errors named too.
        let pgm = dir.join("bad.pgm");
        std::fs::write(&pgm, b"P2 2 x 9\n").unwrap();
        let err = read_image_file(&pgm).unwrap_err();
        assert!(err.contains("bad.pgm") && err.contains("height"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_pgm_is_reported() {
        assert!(read_pgm(b"P6 1 1 255\n\x00\x00\x00")
            .unwrap_err()
            .contains("magic"));
        assert!(read_pgm(b"P5 2 2 255\n\x00").unwrap_err().contains("bytes"));
        assert!(read_pgm(b"P2 1 1 0\n0").unwrap_err().contains("maxval"));
        assert!(read_pgm(b"P2 2 1 9\n3 12")
            .unwrap_err()
            .contains("above maxval"));
        assert!(read_pgm(b"P2 2 x 9\n").unwrap_err().contains("height"));
        assert!(read_pgm(b"P2 2").unwrap_err().contains("ends early"));
    }

    /// A 3 × 3 image with a bright centre pixel: the crystal (ρ 2000) is
    /// the interior node (dual volume h³), the binder (ρ 1000) the four
    /// edge nodes (h³/2) and four corners (h³/4): 2000 / (2000 + 3000).
    #[test]
    fn image_pack_has_the_exact_mass_fraction() {
        let img = read_pgm(b"P2 3 3 255\n0 0 0\n0 200 0\n0 0 0\n").unwrap();
        let geom = image_geometry(&img, 1.0, 128, 0, 1, false);
        let mats = vec![
            LatticeMaterial::elastic("crystal", 1e9, inert_eos(2000.0, 1000.0)),
            LatticeMaterial::elastic("binder", 1e9, inert_eos(1000.0, 1000.0)),
        ];
        let lat = MsdmLattice::new(geom, mats, MsdmOptions::default()).unwrap();
        assert_eq!(lat.material_of(lat.geom.solid_index(1, 1, 0)), Some(0));
        assert_eq!(lat.material_of(lat.geom.solid_index(0, 1, 0)), Some(1));
        assert!((node_mass_fraction(&lat, 0) - 0.4).abs() < 1e-15);
        assert!((node_mass_fraction(&lat, 1) - 0.6).abs() < 1e-15);
        // An L of three bright pixels at the bottom left: corner (¼) and
        // two edges (½ each) of crystal: 2000 · 1.25 / (2000 · 1.25 + 1000 · 2.75).
        let img = read_pgm(b"P2 3 3 255\n0 0 0\n255 0 0\n255 255 0\n").unwrap();
        let geom = image_geometry(&img, 1.0, 128, 0, 1, false);
        let mats = vec![
            LatticeMaterial::elastic("crystal", 1e9, inert_eos(2000.0, 1000.0)),
            LatticeMaterial::elastic("binder", 1e9, inert_eos(1000.0, 1000.0)),
        ];
        let lat = MsdmLattice::new(geom, mats, MsdmOptions::default()).unwrap();
        assert!((node_mass_fraction(&lat, 0) - 2500.0 / 5250.0).abs() < 1e-15);
    }

    #[test]
    fn area_fraction_of_80_percent_ap_in_htpb() {
        // (0.8/1950) / (0.8/1950 + 0.2/920) = 736 / 1126 = 0.653 641 2…
        let phi = area_fraction(0.8, 1950.0, 920.0);
        assert!((phi - 736.0 / 1126.0).abs() < 1e-15, "{phi}");
        assert_eq!(area_fraction(0.5, 1000.0, 1000.0), 0.5);
    }

    #[test]
    fn splitmix_matches_the_reference_stream() {
        // First outputs of SplitMix64 seeded with 0 (the reference
        // implementation of Vigna's xoshiro page).
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn random_pack_is_dense_disjoint_inside_and_reproducible() {
        // 1.2 mm square, 200 µm discs at the 80 wt % AP area fraction.
        let phi = area_fraction(0.8, 1950.0, 920.0);
        let p = random_disc_pack(1.2e-3, 1.2e-3, 2.0e-4, phi, 7).unwrap();
        let n_expected = (phi * 1.44e-6 / (std::f64::consts::PI * 1e-8)).round() as usize;
        assert_eq!(p.centres.len(), n_expected);
        assert!(p.closest_pair() >= 1.0, "{}", p.closest_pair());
        for c in &p.centres {
            assert!(c[0] >= 0.0 && c[0] < 1.2e-3 && c[1] >= 0.0 && c[1] < 1.2e-3);
        }
        // The disc count rounds the fraction: within half a disc.
        let half_disc = 0.5 * std::f64::consts::PI * 1e-8 / 1.44e-6;
        assert!((p.area_fraction() - phi).abs() <= half_disc);
        // Rasterised on 10 µm nodes the node fraction is the disc fraction
        // to the pixelation error.
        let inside = p.rasterise(121, 121, 1e-5);
        let frac = inside.iter().filter(|&&b| b).count() as f64 / inside.len() as f64;
        assert!(
            (frac - p.area_fraction()).abs() < 0.02,
            "{frac} vs {}",
            p.area_fraction()
        );
        let q = random_disc_pack(1.2e-3, 1.2e-3, 2.0e-4, phi, 7).unwrap();
        assert_eq!(p, q);
        let other = random_disc_pack(1.2e-3, 1.2e-3, 2.0e-4, phi, 8).unwrap();
        assert_ne!(p.centres, other.centres);
    }

    #[test]
    fn impossible_packs_are_reported() {
        assert!(random_disc_pack(1.0, 1.0, 0.0, 0.5, 1)
            .unwrap_err()
            .contains("diameter"));
        assert!(random_disc_pack(1.0, 1.0, 0.1, 0.85, 1)
            .unwrap_err()
            .contains("mass_fraction"));
        assert!(random_disc_pack(1.0, 1.0, 2.0, 0.5, 1)
            .unwrap_err()
            .contains("wider"));
    }
}
