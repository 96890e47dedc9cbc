//! The picture itself: a [`Raster`] with a depth buffer and per-pixel part ids; it draws
//! the background, the ground grid and its label, shaded triangles, axes and markers.

use rapier3d::math::Vector;

use crate::view::View;
use crate::{BACKGROUND_BOTTOM, BACKGROUND_TOP, GRID_MAJOR, GRID_MINOR};

pub(crate) struct Raster {
    pub(crate) width: usize,
    pub(crate) height: usize,
    pub(crate) rgb: Vec<u8>,
    pub(crate) ids: Vec<u16>,
    pub(crate) depth: Vec<f32>,
}

pub(crate) fn to_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

impl Raster {
    pub(crate) fn new(width: u32, height: u32) -> Raster {
        let n = width as usize * height as usize;
        Raster {
            width: width as usize,
            height: height as usize,
            rgb: vec![0; 3 * n],
            ids: vec![0; n],
            depth: vec![f32::NEG_INFINITY; n],
        }
    }

    pub(crate) fn fill_background(&mut self) {
        for y in 0..self.height {
            let t = y as f32 / (self.height - 1).max(1) as f32;
            let c: [u8; 3] = std::array::from_fn(|k| {
                to_byte(BACKGROUND_TOP[k] * (1.0 - t) + BACKGROUND_BOTTOM[k] * t)
            });
            for x in 0..self.width {
                self.rgb[3 * (y * self.width + x)..][..3].copy_from_slice(&c);
            }
        }
    }

    pub(crate) fn put(&mut self, x: usize, y: usize, colour: [f32; 3]) {
        self.rgb[3 * (y * self.width + x)..][..3].copy_from_slice(&colour.map(to_byte));
    }

    /// A filled triangle, depth-tested, drawn where it faces the camera.
    pub(crate) fn triangle(
        &mut self,
        view: &View,
        corners: [Vector; 3],
        colour: [f32; 3],
        id: u16,
    ) {
        let Some(p0) = view.project(corners[0]) else {
            return;
        };
        let Some(p1) = view.project(corners[1]) else {
            return;
        };
        let Some(p2) = view.project(corners[2]) else {
            return;
        };
        // Signed area in pixel space (y points down): negative means facing the camera for
        // counter-clockwise, outward-wound faces.
        let area = (p1.0 - p0.0) * (p2.1 - p0.1) - (p2.0 - p0.0) * (p1.1 - p0.1);
        if area >= 0.0 {
            return;
        }
        let min_x = p0.0.min(p1.0).min(p2.0).floor().max(0.0) as usize;
        let max_x = (p0.0.max(p1.0).max(p2.0).ceil().min(self.width as f32)) as usize;
        let min_y = p0.1.min(p1.1).min(p2.1).floor().max(0.0) as usize;
        let max_y = (p0.1.max(p1.1).max(p2.1).ceil().min(self.height as f32)) as usize;
        let edge = |a: (f32, f32, f32), b: (f32, f32, f32), x: f32, y: f32| {
            (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)
        };
        for y in min_y..max_y {
            for x in min_x..max_x {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let w0 = edge(p1, p2, px, py) / area;
                let w1 = edge(p2, p0, px, py) / area;
                let w2 = edge(p0, p1, px, py) / area;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let key = w0 * p0.2 + w1 * p1.2 + w2 * p2.2;
                let i = y * self.width + x;
                if key > self.depth[i] {
                    self.depth[i] = key;
                    self.ids[i] = id;
                    self.put(x, y, colour);
                }
            }
        }
    }

    /// A line, optionally depth-tested, `thickness` pixels wide.
    pub(crate) fn line(
        &mut self,
        view: &View,
        a: Vector,
        b: Vector,
        colour: [f32; 3],
        depth_test: bool,
        thickness: i32,
    ) {
        // Lines are split so that each piece projects (a grid may pass behind the camera).
        const PIECES: usize = 16;
        for k in 0..PIECES {
            let pa = a + (b - a) * (k as f32 / PIECES as f32);
            let pb = a + (b - a) * ((k + 1) as f32 / PIECES as f32);
            let (Some(p), Some(q)) = (view.project(pa), view.project(pb)) else {
                continue;
            };
            // A piece wholly beside the picture draws nothing: skip its pixels.
            let (w, h) = (self.width as f32, self.height as f32);
            if (p.0 < 0.0 && q.0 < 0.0)
                || (p.0 >= w && q.0 >= w)
                || (p.1 < 0.0 && q.1 < 0.0)
                || (p.1 >= h && q.1 >= h)
            {
                continue;
            }
            let steps = (q.0 - p.0)
                .abs()
                .max((q.1 - p.1).abs())
                .ceil()
                .clamp(1.0, 8192.0) as usize;
            for s in 0..=steps {
                let t = s as f32 / steps as f32;
                let (x, y) = (p.0 + (q.0 - p.0) * t, p.1 + (q.1 - p.1) * t);
                let key = p.2 + (q.2 - p.2) * t;
                for dy in 0..thickness {
                    let (xi, yi) = (x.floor() as i64, y.floor() as i64 + i64::from(dy));
                    if xi < 0 || yi < 0 || xi >= self.width as i64 || yi >= self.height as i64 {
                        continue;
                    }
                    let i = yi as usize * self.width + xi as usize;
                    if !depth_test || key >= self.depth[i] {
                        self.put(xi as usize, yi as usize, colour);
                    }
                }
            }
        }
    }

    /// The ground grid on z = 0, around the point below the camera's target, behind
    /// whatever stands on it.
    pub(crate) fn grid(&mut self, view: &View, spacing: f32) {
        let n = (view.visible_half_height() * 3.0 / spacing)
            .ceil()
            .clamp(1.0, 100.0) as i32;
        let half = n as f32 * spacing;
        let cx = (view.target.x / (5.0 * spacing)).round() * 5.0 * spacing;
        let cy = (view.target.y / (5.0 * spacing)).round() * 5.0 * spacing;
        for k in -n..=n {
            let major = (cx / spacing).round() as i64 + i64::from(k);
            let colour = if major % 5 == 0 {
                GRID_MAJOR
            } else {
                GRID_MINOR
            };
            let o = k as f32 * spacing;
            self.line(
                view,
                Vector::new(cx + o, cy - half, 0.0),
                Vector::new(cx + o, cy + half, 0.0),
                colour,
                true,
                1,
            );
            let major = (cy / spacing).round() as i64 + i64::from(k);
            let colour = if major % 5 == 0 {
                GRID_MAJOR
            } else {
                GRID_MINOR
            };
            self.line(
                view,
                Vector::new(cx - half, cy + o, 0.0),
                Vector::new(cx + half, cy + o, 0.0),
                colour,
                true,
                1,
            );
        }
    }

    /// `text` in the bottom-left corner on a light box (the grid's scale), scaled with
    /// the picture; left out when the picture is too small to hold it.
    pub(crate) fn label(&mut self, text: &str) {
        let scale = (self.height / 240).max(1);
        let (cw, ch) = (6 * scale, 7 * scale);
        let (pad, n) = (2 * scale, text.chars().count());
        let (w, h) = (n * cw + 2 * pad, ch + 2 * pad);
        if w + 2 > self.width || h + 2 > self.height {
            return;
        }
        let (x0, y0) = (2, self.height - h - 2);
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.put(x, y, [1.0, 1.0, 1.0]);
            }
        }
        for (k, c) in text.chars().enumerate() {
            let Some(rows) = glyph(c) else { continue };
            for (row, bits) in rows.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0x10 >> col) == 0 {
                        continue;
                    }
                    for dy in 0..scale {
                        for dx in 0..scale {
                            let x = x0 + pad + k * cw + col * scale + dx;
                            let y = y0 + pad + row * scale + dy;
                            self.put(x, y, [0.1, 0.1, 0.15]);
                        }
                    }
                }
            }
        }
    }

    /// A filled disc of `radius` pixels, drawn on top.
    pub(crate) fn dot(&mut self, view: &View, p: Vector, radius: f32, colour: [f32; 3]) {
        self.disc(view, p, radius, colour, 0.0);
    }

    /// A ring of `radius` pixels, drawn on top.
    pub(crate) fn ring(&mut self, view: &View, p: Vector, radius: f32, colour: [f32; 3]) {
        self.disc(view, p, radius, colour, radius - 2.0);
    }

    pub(crate) fn disc(
        &mut self,
        view: &View,
        p: Vector,
        outer: f32,
        colour: [f32; 3],
        inner: f32,
    ) {
        let Some((cx, cy, _)) = view.project(p) else {
            return;
        };
        let r = outer.ceil() as i64;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (cx.floor() as i64 + dx, cy.floor() as i64 + dy);
                if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
                    continue;
                }
                let d = ((dx * dx + dy * dy) as f32).sqrt();
                if d <= outer && d >= inner {
                    self.put(x as usize, y as usize, colour);
                }
            }
        }
    }
}

/// A grid spacing as a person writes it: `20`, `0.5`, `1000`.
pub(crate) fn format_mm(mm: f32) -> String {
    let text = format!("{mm:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A 5 × 7 bitmap of each character the picture's label uses (rows top to bottom, the
/// five low bits of each row left to right).
pub(crate) fn glyph(c: char) -> Option<[u8; 7]> {
    Some(match c {
        '0' => [0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e],
        '1' => [0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e],
        '2' => [0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f],
        '3' => [0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e],
        '4' => [0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02],
        '5' => [0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e],
        '6' => [0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e],
        '7' => [0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e],
        '9' => [0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c],
        'g' => [0x00, 0x00, 0x0f, 0x11, 0x0f, 0x01, 0x0e],
        'r' => [0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10],
        'i' => [0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e],
        'd' => [0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f],
        'm' => [0x00, 0x00, 0x1a, 0x15, 0x15, 0x11, 0x11],
        ' ' => [0; 7],
        _ => return None,
    })
}

/// The 1, 2, 5 × 10ⁿ mm spacing nearest above `raw`.
pub(crate) fn nice_spacing(raw: f32) -> f32 {
    let raw = raw.max(1.0e-3);
    let decade = 10f32.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * decade)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_spacings_are_one_two_five() {
        assert_eq!(nice_spacing(0.9), 1.0);
        assert_eq!(nice_spacing(1.5), 2.0);
        assert_eq!(nice_spacing(30.0), 50.0);
        assert_eq!(nice_spacing(51.0), 100.0);
    }

    #[test]
    fn spacings_print_as_people_write_them() {
        assert_eq!(format_mm(20.0), "20");
        assert_eq!(format_mm(0.5), "0.5");
        assert_eq!(format_mm(1000.0), "1000");
        assert!("grid 0.5 mm".chars().all(|c| glyph(c).is_some()));
        assert!("0123456789".chars().all(|c| glyph(c).is_some()));
    }
}
