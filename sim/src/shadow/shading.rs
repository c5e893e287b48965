//! Shading a shadowed pixel: exact (shade registers per shadowing light) or the seed's
//! §6 table (normal class, light mask, counter).

use super::*;

/// How a shadowed pixel is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Shading {
    /// Exact (the default): each polygon's spans carry, per shadowing light, its
    /// intensity without that light (span words with `chan ≥ 1`, shade registers per
    /// processor), and the readout removes the shadowed share of each light's difference.
    /// Depends on nothing but the pixel's own surface and lights.
    #[default]
    Exact,
    /// The seed's §6 table: the summed intensity times a factor indexed by (normal class,
    /// light mask, counter), computed with one direction per light from the scene centre.
    Table,
}

/// Attenuation table of seed 001 §6, indexed by (normal class, light mask, area count):
/// `F = (a + Σ_l w(c,l)·(1 − s_l)) / (a + Σ_l w(c,l))`, with `w(c,l) = I_l·max(0, n_c·d_l)`,
/// `d_l` the direction from the scene centre to light l (the distant-light assumption),
/// `s_l` = 1 if light l's mask bit is set (point light) or `count/k` (the area light), and
/// `a` the ambient level. Entries are Q0.8 (256 = 1), computed once per frame like a ROM.
///
/// In [`Shading::Exact`] the same table holds `F = 256` and, in its drop column, the
/// shadowed share `s_0` of the first shadowing light in Q0.8 (`G`); the readout then
/// computes `c − Σ_l ((max(0, c − sh_l)·G_l + 128) >> 8)` over the pixel's shade
/// registers `sh_l` (the intensity without light `l`), see
/// [`pixelproc_formats::core_stream::shade_rgb`].
#[derive(Clone, Debug)]
pub struct FactorTable {
    bits: u32,
    counts: u32,
    entries: Vec<u16>,
    drops: Vec<u16>,
    /// Per shade channel, the light's mask bit (`None`: the area light's counter).
    channels: Vec<Option<u8>>,
    /// Number of samples of the area light (0 if none).
    pub area_samples: u32,
    /// Number of point lights with mask bits.
    pub point_lights: u32,
    /// The shading mode the table implements.
    pub shading: Shading,
}

impl FactorTable {
    /// The table of `shading` for the scene's shadowing lights (in channel order).
    pub fn for_mode(ls: &LoadedScene, lights: &[ShadowLight], shading: Shading) -> FactorTable {
        match shading {
            Shading::Table => FactorTable::new(ls, lights),
            Shading::Exact => FactorTable::exact(lights),
        }
    }

    /// Shape of the table for `lights`: mask bits, counter values, area samples.
    fn shape(lights: &[ShadowLight]) -> (u32, u32, u32) {
        let bits = lights.iter().filter(|l| l.bit.is_some()).count() as u32;
        let area = lights.iter().find(|l| l.bit.is_none());
        let k = area.map(|l| l.samples.len() as u32).unwrap_or(0);
        (bits, k + 1, k)
    }

    /// The exact-shading table: `F = 256`, `G` = shadowed share of channel 1's light.
    pub fn exact(lights: &[ShadowLight]) -> FactorTable {
        let (bits, counts, k) = FactorTable::shape(lights);
        let n = 256 * (1usize << bits) * counts as usize;
        let channels: Vec<Option<u8>> = lights.iter().map(|l| l.bit).collect();
        let mut drops = vec![0u16; n];
        for (i, d) in drops.iter_mut().enumerate() {
            let cnt = (i % counts as usize) as u8;
            let mask = ((i / counts as usize) & ((1 << bits) - 1)) as u8;
            if let Some(&first) = channels.first() {
                *d = share(first, mask, cnt, k);
            }
        }
        FactorTable {
            bits,
            counts,
            entries: vec![256; n],
            drops,
            channels,
            area_samples: k,
            point_lights: bits,
            shading: Shading::Exact,
        }
    }

    /// Builds the seed's table (§6) for the scene's lights.
    pub fn new(ls: &LoadedScene, lights: &[ShadowLight]) -> FactorTable {
        let centre = scene_centre(ls);
        let (bits, counts, k) = FactorTable::shape(lights);
        let dir =
            |i: usize| (DVec3::from(ls.scene.lights[i].position) - centre).normalize_or(DVec3::Y);
        let mut entries = vec![0u16; 256 * (1usize << bits) * counts as usize];
        for c in 0..256usize {
            let n = class_normal(c as u8);
            let w = |i: usize| ls.scene.lights[i].intensity * n.dot(dir(i)).max(0.0);
            let total: f64 = ls.scene.ambient
                + ls.scene
                    .lights
                    .iter()
                    .enumerate()
                    .map(|(i, _)| w(i))
                    .sum::<f64>();
            for mask in 0..(1usize << bits) {
                for cnt in 0..counts {
                    let mut lit = total;
                    for l in lights {
                        let s = match l.bit {
                            Some(b) => ((mask >> b) & 1) as f64,
                            None => cnt as f64 / k as f64,
                        };
                        lit -= w(l.index) * s;
                    }
                    let f = if total > 0.0 {
                        (lit / total).clamp(0.0, 1.0)
                    } else {
                        1.0
                    };
                    entries[(c << bits | mask) * counts as usize + cnt as usize] =
                        (f * 256.0).round() as u16;
                }
            }
        }
        let n = entries.len();
        FactorTable {
            bits,
            counts,
            entries,
            drops: vec![0; n],
            channels: Vec::new(),
            area_samples: k,
            point_lights: bits,
            shading: Shading::Table,
        }
    }

    fn index(&self, s: &ProcState) -> usize {
        let mask = (s.mask as usize) & ((1 << self.bits) - 1);
        let cnt = (s.count as usize).min(self.counts as usize - 1);
        ((s.nclass as usize) << self.bits | mask) * self.counts as usize + cnt
    }

    /// The factor (Q0.8, 256 = 1) for a pixel's state.
    pub fn factor(&self, s: &ProcState) -> u16 {
        self.entries[self.index(s)]
    }

    /// The drop weight of shade register 1 (Q0.8) for a pixel's state (0 in table mode).
    pub fn drop_weight(&self, s: &ProcState) -> u16 {
        self.drops[self.index(s)]
    }

    /// Number of shade channels the exact mode uses (0 in table mode).
    pub fn channels(&self) -> usize {
        self.channels.len()
    }

    /// Light-mask bits the table is indexed by (one per shadowing point light).
    pub fn mask_bits(&self) -> u32 {
        self.bits
    }

    /// Counter values the table is indexed by (`area_samples + 1`).
    pub fn counts(&self) -> u32 {
        self.counts
    }

    /// Every entry as `(nclass, mask, count, factor, drop)`: what a hardware table holds.
    pub fn entries(&self) -> impl Iterator<Item = (u8, u8, u8, u16, u16)> + '_ {
        let (bits, counts) = (self.bits, self.counts as usize);
        self.entries
            .iter()
            .zip(&self.drops)
            .enumerate()
            .map(move |(i, (&f, &g))| {
                let cnt = i % counts;
                let rest = i / counts;
                let mask = rest & ((1 << bits) - 1);
                ((rest >> bits) as u8, mask as u8, cnt as u8, f, g)
            })
    }

    /// Shadowed fraction of the pixel's lights, 0..=255, for the shadow AOV; 0 on the
    /// background (no surface: shadow spans still toggle its flags, but nothing is shaded).
    pub fn shadow_level(&self, s: &ProcState) -> u8 {
        let n = self.point_lights + (self.area_samples > 0) as u32;
        if n == 0 || s.zb == Z_FAR {
            return 0;
        }
        let pts = (s.mask as u32 & ((1 << self.bits) - 1)).count_ones() as f64;
        let area = if self.area_samples > 0 {
            s.count as f64 / self.area_samples as f64
        } else {
            0.0
        };
        (((pts + area) / n as f64) * 255.0).round() as u8
    }

    /// The shaded colour of one covered pixel of intensity `rgb` (RGB888) with state `s`
    /// and shade registers 2.. `more` (empty if unused).
    pub fn shade_pixel(&self, rgb: u32, s: &ProcState, more: &[u32]) -> u32 {
        if self.channels.len() <= 1 {
            let i = self.index(s);
            let (f, g) = (self.entries[i] as u32, self.drops[i] as u32);
            // Factor 1 and nothing dropped leave every channel as it is:
            // `(c·256 + 128) >> 8 = c` and `(d·0 + 128) >> 8 = 0`.
            if f == 256 && g == 0 {
                return rgb;
            }
            return shade_rgb(rgb, s.sh, f, g);
        }
        let c = pixelproc_formats::unpack_rgb(rgb);
        let mut out = c.map(|v| v as u32);
        for (l, &bit) in self.channels.iter().enumerate() {
            let g = share(bit, s.mask, s.count, self.area_samples) as u32;
            let sh = if l == 0 {
                s.sh
            } else {
                more.get(l - 1).copied().unwrap_or(0)
            };
            let sv = pixelproc_formats::unpack_rgb(sh);
            for k in 0..3 {
                let d = (c[k] as u32).saturating_sub(sv[k] as u32);
                out[k] = out[k].saturating_sub((d * g + 128) >> 8);
            }
        }
        pixelproc_formats::pack_rgb(out.map(|v| v as u8))
    }
}

/// The shadowed share of one light, Q0.8: 256 if a point light's mask bit is set,
/// `round(256·count/k)` for the area light (`bit = None`) of `k` samples.
pub(super) fn share(bit: Option<u8>, mask: u8, count: u8, k: u32) -> u16 {
    match bit {
        Some(b) => ((mask >> b) & 1) as u16 * 256,
        None if k > 0 => ((256 * count.min(k as u8) as u32 + k / 2) / k) as u16,
        None => 0,
    }
}

/// "Correct the intensity and store it in the frame buffer" (§2), for one row of
/// processors as it is read out: every covered pixel's colour becomes
/// [`FactorTable::shade_pixel`] of it (table mode: `(c·F + 128) >> 8`). `more` holds the
/// row's shade registers 2.. ([`MORE_SHADE`] per pixel), or is empty.
pub fn shade_row(px: &mut [ProcState], more: &[u32], table: &FactorTable) {
    let stride = if more.is_empty() { 0 } else { MORE_SHADE };
    for (i, s) in px.iter_mut().enumerate() {
        if s.zb == Z_FAR {
            continue;
        }
        let m = &more[i * stride..(i + 1) * stride];
        s.rgb = table.shade_pixel(s.rgb, s, m);
    }
}

/// Applies each pixel centre's shadow shading to an anti-aliased RGB8 image (the shadow
/// flags and shade registers are those of the surface visible at the pixel centre; an
/// approximation at shadow and object edges, documented in `docs/shadows.md`).
pub fn apply_to_rgb8(rgb: &mut [u8], frame: &crate::render::Frame, table: &FactorTable) {
    let stride = if frame.more.is_empty() { 0 } else { MORE_SHADE };
    rgb.par_chunks_mut(3)
        .zip(frame.px.par_iter())
        .enumerate()
        .for_each(|(i, (c, s))| {
            if s.zb == Z_FAR {
                return;
            }
            let m = &frame.more[i * stride..(i + 1) * stride];
            let out = table.shade_pixel(pixelproc_formats::pack_rgb([c[0], c[1], c[2]]), s, m);
            c.copy_from_slice(&pixelproc_formats::unpack_rgb(out));
        });
}
