//! The power-heuristic weight of one strategy (s, t) against every strategy
//! that could have sampled the same path, in O(s + t).
//!
//! Number the path's vertices x₀ (on the light) … x_k (the lens), k = s + t − 1,
//! and let L_i be the density of x_i sampled from the light side (from
//! x_{i−1}; for x₀ the start of a light subpath) and C_i the density from
//! the camera side (from x_{i+1}). Strategy s′ (s′ light vertices, t′ = k + 1 − s′)
//! samples the path with density
//!
//! ```text
//! p_{s′} = f(s′) · Π_{1 ≤ i < s′} L_i · Π_{i ≥ max(s′,1)} C_i,
//! f(0) = C₀,  f(1) = N,  f(s′ ≥ 2) = L₀,
//! ```
//!
//! where N is the density next-event estimation gives x₀ from x₁ (s′ = 1
//! resamples the light point instead of connecting to a light subpath's
//! start). Ratios of neighbouring products are L_i/C_i, so the ratios
//! r_{s′} = p_{s′}/p_s follow by one walk down and one walk up from s
//! (Veach 1997, §10.3.4), and the weight is 1/(1 + Σ_{s′ ≠ s} r_{s′}²).
//!
//! A strategy counts only where it could have made the path: its connection
//! must join two vertices not behind a Dirac BSDF; t′ = 0 (a light path
//! hitting the lens) is never traced, nor is s′ = t′ = 1 (a light seen
//! directly is the camera path's; points and delta suns stay invisible, as
//! in the path tracer). Zero densities propagate: a point light has C₀ = 0,
//! so s′ = 0 drops out by itself. Products are taken in f64.

use super::vertex::Vertex;

/// One connection's path, as the two subpath prefixes and the densities the connection changes.
pub(super) struct Strategy<'a> {
    /// The light subpath's first s vertices (for s = 1, the light next-event estimation picked).
    pub light: &'a [Vertex],
    /// The camera subpath's first t vertices (for s = 0, the last is on a light).
    pub camera: &'a [Vertex],
    /// L₀: density of x₀ as a light subpath's start (light pick × position or direction).
    pub emit: f32,
    /// N: density of x₀ as next-event estimation from x₁ samples it (light pick included).
    pub nee: f32,
    /// C of y_{s−1}: density from z_{t−1} (camera side).
    pub y_rev: f32,
    /// C of y_{s−2}: density from y_{s−1} arriving from z_{t−1}.
    pub y_prev_rev: f32,
    /// L of z_{t−1}: density from y_{s−1} (for s = 0: unused, x₀ takes `emit`).
    pub z_rev: f32,
    /// L of z_{t−2}: density from z_{t−1} arriving from y_{s−1} (for s = 0: from the light point).
    pub z_prev_rev: f32,
}

impl Strategy<'_> {
    fn s(&self) -> usize {
        self.light.len()
    }

    fn k(&self) -> usize {
        self.light.len() + self.camera.len() - 1
    }

    /// (L_i, C_i) of path vertex i, with the connection's densities in place.
    fn densities(&self, i: usize) -> (f64, f64) {
        let (s, t) = (self.s(), self.camera.len());
        let (l, c) = if i < s {
            let v = &self.light[i];
            let c = if i + 1 == s {
                self.y_rev
            } else if i + 2 == s {
                self.y_prev_rev
            } else {
                v.pdf_rev
            };
            (v.pdf_fwd, c)
        } else {
            let j = self.k() - i;
            let v = &self.camera[j];
            let l = if j + 1 == t {
                self.z_rev
            } else if j + 2 == t {
                self.z_prev_rev
            } else {
                v.pdf_rev
            };
            (l, v.pdf_fwd)
        };
        let l = if i == 0 { self.emit } else { l };
        (l as f64, c as f64)
    }

    /// True when a connection may end at path vertex i (x₀ always: it is a light).
    fn connectable(&self, i: usize) -> bool {
        if i == 0 {
            return true;
        }
        let s = self.s();
        if i < s {
            self.light[i].connectable()
        } else {
            self.camera[self.k() - i].connectable()
        }
    }

    /// True when strategy s′ could have sampled this path.
    fn counts(&self, s: usize) -> bool {
        let k = self.k();
        if s > k || (s == 1 && k == 1) {
            return false;
        }
        s == 0 || (self.connectable(s - 1) && self.connectable(s))
    }

    /// f(s′): the density the strategy gives x₀.
    fn origin(&self, s: usize, c0: f64) -> f64 {
        match s {
            0 => c0,
            1 => self.nee as f64,
            _ => self.emit as f64,
        }
    }
}

/// The power-heuristic weight of the strategy `st` describes (0 when its own density is 0).
pub(super) fn weight(st: &Strategy) -> f32 {
    let (s, k) = (st.s(), st.k());
    if k == 1 {
        // Only s = 0 samples a light seen directly.
        return 1.0;
    }
    let c0 = st.densities(0).1;
    let own = st.origin(s, c0);
    // The product defining p_s: a zero factor means the strategy cannot
    // sample the path (the ratio walks below divide by these).
    let base = s.max(1);
    let zero_factor =
        (1..base).any(|i| st.densities(i).0 == 0.0) || (base..=k).any(|i| st.densities(i).1 == 0.0);
    if own == 0.0 || zero_factor {
        return 0.0;
    }
    let mut sum = 0.0f64;
    // Down: A_{i} = A_{i+1} · C_i / L_i for 1 ≤ i < base.
    let mut r = 1.0f64;
    for i in (1..base).rev() {
        let (l, c) = st.densities(i);
        r = step(r, c, l);
        if st.counts(i) {
            sum += sq(r * st.origin(i, c0) / own);
        }
    }
    if s >= 1 && st.counts(0) {
        // p₀ = C₀ · A₁, and r already holds A₁/A_base.
        let a1 = if base == 1 { 1.0 } else { r };
        sum += sq(a1 * c0 / own);
    }
    // Up: A_{i+1} = A_i · L_i / C_i for base ≤ i < k.
    let mut r = 1.0f64;
    if s == 0 && st.counts(1) {
        // p₁ = N · A₁ against p₀ = C₀ · A₁.
        sum += sq(st.nee as f64 / own);
    }
    for i in base..k {
        let (l, c) = st.densities(i);
        r = step(r, l, c);
        if i + 1 != s && st.counts(i + 1) {
            sum += sq(r * st.origin(i + 1, c0) / own);
        }
    }
    (1.0 / (1.0 + sum)) as f32
}

/// `r · num / den`, keeping an exact zero when `num` is zero (even if `r` overflowed).
#[inline]
fn step(r: f64, num: f64, den: f64) -> f64 {
    if num == 0.0 || r == 0.0 {
        0.0
    } else {
        r * num / den
    }
}

#[inline]
fn sq(x: f64) -> f64 {
    x * x
}
