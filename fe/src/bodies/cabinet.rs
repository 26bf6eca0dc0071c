//! The cabinet's FE model: S8R steel panels (sides and back crowned outwards, front with the
//! door opening) and a chipboard worktop on B32 frame beams along the edges (folded-sheet
//! boxes); top rails under the springs; a base frame of rails with the feet and the friction
//! dampers' brackets; the door and the pump, valves and electronics as point masses. The feet
//! are SPRING1 elements to the ground. No rigid DOF: the feet hold it (seed paper: the floor
//! contact is part of the FE model, so the cabinet's modes are those on its feet).
//!
//! On its feet it sways at 26.4 Hz (y) and 27.4 Hz (x) and yaws at 43.6 Hz (issue 19: >= 25 Hz;
//! no mode lies below the first sway). Two things put them there. The body must not rack: the
//! edges are closed folded sections (`Folded`), and the sway modes keep 79-84 % of their strain
//! energy in the feet. And the feet: on the rubber feet (1e6 N/m vertical, 2e5 N/m
//! horizontal) even a rigid cabinet of this mass and CoG (28.9 kg, 0.43 m up) sways at 20.7 Hz
//! (26.5 kg: 21.6 Hz), and would need its CoG at 0.15-0.2 m for 25 Hz, which a 4 kg worktop at
//! 0.85 m and a 4 kg door at 0.45 m forbid. So the feet are adjustable screw feet with thin
//! rubber pads, twice as stiff (`Cabinet::default`).
//!
//! Numbers: reference-machine.md ("FE models"); engineering estimates unless it names a source.

use super::drum::steel;
use super::geometry::{beam_line, near, shell_grid};
use crate::mesh::{Material, Mesh, Section};
use std::f64::consts::PI;

/// A part carried as point masses: `kg` spread evenly over the nodes of the base rails and
/// frame within `radius` of `at` (a pump bolted to the base, a valve block on the back frame).
#[derive(Clone, Debug)]
pub struct Carried {
    /// The element set's name in the deck.
    pub name: &'static str,
    pub kg: f64,
    pub at: [f64; 3],
    pub radius: f64,
}

/// The cabinet's parameters; `Default` is the reference machine.
#[derive(Clone, Debug)]
pub struct Cabinet {
    /// Half width (x and y) and height, m.
    pub half: f64,
    pub height: f64,
    /// Steel panels (sides, back, front), m.
    pub sheet: f64,
    /// Outward bulge of the side panels and of the back at their centre, m.
    pub bulge: f64,
    pub back_bulge: f64,
    /// Door opening: centre height and radius, m (front panel x = +half).
    pub door_z: f64,
    pub door_radius: f64,
    /// Depth of the opening's drawn collar (into the cabinet), m, and the O-grid's elements
    /// from the opening out to the square about it.
    pub collar: f64,
    pub n_ring: usize,
    /// The opening's surround is drawn in: the edge lies `recess` behind the panel's plane,
    /// rising to it at the square's sides (a shallow funnel, as pressed front panels have; its
    /// membrane action carries the door), m.
    pub recess: f64,
    /// The door (frame, glass bowl, hinge, lock), kg: point masses on the opening's edge nodes,
    /// which add its inertia but no stiffness (the door hangs on a hinge and a latch; it does
    /// not stiffen the panel as a welded ring would).
    pub door_mass: f64,
    /// Worktop: a chipboard plate of this mass (kg) covering the top, instead of a steel sheet.
    pub worktop_mass: f64,
    pub worktop: Material,
    /// The 12 edges (posts, top and base frame): folded-sheet closed sections.
    pub edge: Folded,
    /// Top rails under the springs: section depth (vertical, ccx's 1-direction) and thickness, m.
    pub rail_depth: f64,
    pub rail_thickness: f64,
    /// Base rails (feet and dampers): depth (vertical) and width, m; solid steel bars standing
    /// in for the base's pressed channels.
    pub base_rail_depth: f64,
    pub base_rail_width: f64,
    /// Feet at (+-foot, +-foot, 0) on the base rails along y; stiffness per foot, N/m.
    pub foot: f64,
    pub k_vertical: f64,
    pub k_horizontal: f64,
    /// Friction dampers' cabinet ends at (+-x, +-y, z) (DAMPER_1..4: (+, +), (+, -), (-, +),
    /// (-, -)), each on a bracket standing on the base rail along x at y = +-`damper_rail`.
    pub damper: [f64; 3],
    pub damper_rail: f64,
    /// The brackets' solid square section, m.
    pub bracket: f64,
    /// Pump, valves, electronics.
    pub carried: Vec<Carried>,
    /// Elements across (x, y) and up (z).
    pub n_across: usize,
    pub n_up: usize,
}

/// A closed thin-walled square section of folded sheet: outer side and wall, m.
#[derive(Clone, Debug)]
pub struct Folded {
    pub side: f64,
    pub wall: f64,
}

impl Folded {
    /// Cross-section area, m^2.
    pub fn area(&self) -> f64 {
        let inner = self.side - 2.0 * self.wall;
        self.side * self.side - inner * inner
    }

    /// Second moment of area about either axis, m^4.
    pub fn second_moment(&self) -> f64 {
        let inner = self.side - 2.0 * self.wall;
        (self.side.powi(4) - inner.powi(4)) / 12.0
    }

    /// B32 takes solid rectangles: the solid square with the box's bending stiffness, of a
    /// steel whose density gives the box's mass per metre (`material` names it). Its torsion
    /// constant (0.141 b^4) is then within 15 % of the box's (4 A_m^2 t / perimeter).
    pub fn section(&self, material: &str, normal: [f64; 3]) -> Section {
        let b = (12.0 * self.second_moment()).powf(0.25);
        let mut m = steel();
        m.name = material.into();
        m.rho *= self.area() / (b * b);
        Section::Beam {
            width: b,
            height: b,
            normal,
            material: m,
        }
    }
}

/// Particleboard (EN 312 P2, the usual worktop): E 2.5 GPa (estimate from the standard's
/// bending modulus 1.6-2.5 GPa), density 650 kg/m^3.
pub fn chipboard() -> Material {
    Material {
        name: "CHIPBOARD".into(),
        e: 2.5e9,
        nu: 0.3,
        rho: 650.0,
    }
}

impl Default for Cabinet {
    fn default() -> Self {
        Cabinet {
            half: 0.30,
            height: 0.85,
            sheet: 0.0007,
            // A pressed crown standing in for a panel's crown and beads (estimate): with 2 mm
            // the sheets drummed at 11-18 Hz, among the on-feet modes; with 8 mm (and the
            // folded edges) the first panel mode is 48 Hz. A 4 mm back drums at 35 Hz and
            // takes 15 % of the x sway's strain energy.
            bulge: 0.008,
            back_bulge: 0.008,
            door_z: 0.45,
            door_radius: 0.20,
            collar: 0.025,
            n_ring: 4,
            recess: 0.03,
            door_mass: 4.0,
            worktop_mass: 4.0,
            worktop: chipboard(),
            // The two panels' flanges at each edge, folded and screwed into a 20 x 20 mm box
            // of 0.7 mm sheet (estimate; 2.5 kg more steel than bare sheet edges). With 4 mm
            // solid bars instead the sheets racked and bent: on the feet 19-21 % of
            // the sway modes' strain energy lay outside the feet, with the boxes 7-10 % (16-21 %
            // on the stiffer feet below, mostly in the front panel beside the opening). 25 mm
            // boxes gain nothing (their mass eats their stiffness), nor do corner plates at
            // the feet.
            edge: Folded {
                side: 0.020,
                wall: 0.0007,
            },
            rail_depth: 0.025,
            rail_thickness: 0.004,
            base_rail_depth: 0.030,
            base_rail_width: 0.006,
            // Near the corners; adjustable screw feet with thin rubber pads, twice the issue's
            // rubber feet (1e6 N/m vertical, 2e5 N/m horizontal), their 5:1 ratio kept
            // (estimates). Horizontal: the pad's shear G A / t; a 40 mm pad 4 mm thick of
            // Shore A 60 (G 1.2 MPa by Gent's relation) gives 3.8e5 N/m, the M10 screw's
            // bending (25 mm free) 9e6 in series. Vertical: that pad alone (bonded, shape
            // factor 2.5) is about 1e7 N/m, so 2e6 is the floor and the foot's bracket in
            // series. Measured (ccx): with the feet the sway pair is 19.7 / 20.1 Hz,
            // with 3e5 / 2e6 24.6 / 25.4, with 4e5 / 1.5e6 24.9 / 25.7, with 4e5 / 2e6
            // 26.4 / 27.4.
            foot: 0.28,
            k_vertical: 2e6,
            k_horizontal: 4e5,
            damper: [0.18, 0.27, 0.03],
            damper_rail: 0.26,
            bracket: 0.02,
            carried: vec![
                // Drain pump: base, front right (behind the filter flap).
                Carried {
                    name: "CAB_PUMP",
                    kg: 1.0,
                    at: [0.28, -0.16, 0.0],
                    radius: 0.03,
                },
                // Main control board (motor inverter): base, rear left.
                Carried {
                    name: "CAB_BOARD",
                    kg: 0.5,
                    at: [-0.28, 0.16, 0.0],
                    radius: 0.03,
                },
                // Inlet valves: top of the back, left.
                Carried {
                    name: "CAB_VALVES",
                    kg: 0.3,
                    at: [-0.30, 0.20, 0.85],
                    radius: 0.03,
                },
                // Control panel board: top of the front, right.
                Carried {
                    name: "CAB_PANEL",
                    kg: 0.2,
                    at: [0.30, -0.15, 0.85],
                    radius: 0.03,
                },
            ],
            // 15 across puts nodes every 20 mm: on the feet (0.28), the base rails (0.26), the
            // damper brackets (0.18) and the top rails (-0.10, 0.12).
            n_across: 15,
            n_up: 17,
        }
    }
}

impl Cabinet {
    /// Worktop thickness that gives `worktop_mass`, m.
    pub fn worktop_thickness(&self) -> f64 {
        self.worktop_mass / (4.0 * self.half * self.half * self.worktop.rho)
    }

    /// The friction dampers' cabinet ends, DAMPER_1..4.
    pub fn damper_points(&self) -> [[f64; 3]; 4] {
        let [x, y, z] = self.damper;
        [[x, y, z], [x, -y, z], [-x, y, z], [-x, -y, z]]
    }

    /// The front panel (x = +half) with the circular door opening and its drawn collar; returns
    /// the opening's edge nodes. Below and above the square [-half, half]^2 about the opening's
    /// centre the panel is a plain grid; the square is an O-grid of four patches between the
    /// circle and the square's sides (seams on the diagonals), so the opening is round and its
    /// edge nodes meet the side panels' and the frame's nodes.
    fn front(&self, m: &mut Mesh, sheet: &Section) -> Vec<usize> {
        let (a, h, na) = (self.half, self.height, self.n_across);
        let (zc, r) = (self.door_z, self.door_radius);
        let dz = h / self.n_up as f64;
        let (z0, z1) = (zc - a, zc + a);
        let below = (z0 / dz).round() as usize;
        let above = ((h - z1) / dz).round() as usize;
        let side = ((z1 - z0) / dz).round() as usize;
        assert!(
            (below as f64 * dz - z0).abs() < 1e-9 && (h - above as f64 * dz - z1).abs() < 1e-9,
            "the opening's square must end on the side panels' node rows"
        );
        let s = |u: f64| -a + 2.0 * a * u;
        shell_grid(m, "CAB_FRONT", sheet, na, below, false, |u, v| {
            [a, s(u), z0 * v]
        });
        shell_grid(m, "CAB_FRONT", sheet, na, above, false, |u, v| {
            [a, s(u), z1 + (h - z1) * v]
        });
        // Patches counter-clockwise seen from the front (angle from +y towards +z), each from
        // the circle (u = 0) out to its side of the square (u = 1): right side (y = +a), top,
        // left, bottom. u x v points along +x, as on the rest of the cabinet.
        let corners = [[a, -a], [a, a], [-a, a], [-a, -a]].map(|[y, z]| [y, zc + z]);
        let counts = [side, na, side, na];
        let mut edge = Vec::new();
        for p in 0..4 {
            let (c0, c1) = (corners[p], corners[(p + 1) % 4]);
            let phi0 = -PI / 4.0 + p as f64 * PI / 2.0;
            let at = |u: f64, v: f64| {
                let phi = phi0 + v * PI / 2.0;
                let arc = [r * phi.cos(), zc + r * phi.sin()];
                let sq = [c0[0] + v * (c1[0] - c0[0]), c0[1] + v * (c1[1] - c0[1])];
                let x = a - self.recess * (1.0 - u) * (1.0 - u);
                [
                    x,
                    arc[0] + u * (sq[0] - arc[0]),
                    arc[1] + u * (sq[1] - arc[1]),
                ]
            };
            let g = shell_grid(m, "CAB_FRONT", sheet, self.n_ring, counts[p], false, at);
            edge.extend(g.iter().filter(|((i, _), _)| *i == 0).map(|(_, &id)| id));
            // The collar: the opening's edge drawn in by `collar` (the gasket's bead clamps
            // onto it).
            let collar = Section::Shell {
                thickness: self.sheet,
                material: steel(),
            };
            shell_grid(m, "CAB_COLLAR", &collar, 1, counts[p], false, |u, v| {
                let mut q = at(0.0, v);
                q[0] -= self.collar * u;
                q
            });
        }
        edge.sort_unstable();
        edge.dedup();
        edge
    }

    /// The door's mass spread evenly along the opening's edge: each edge node carries the
    /// share of the angle half-way to its neighbours (the O-grid's sides and top differ in
    /// spacing), as point masses (parts CAB_DOOR, CAB_DOOR_2, .. by mass).
    fn door(&self, m: &mut Mesh, edge: &[usize]) {
        let angle = |id: usize| {
            let p = m.nodes[id - 1];
            (p[2] - self.door_z).atan2(p[1])
        };
        let mut ring: Vec<(f64, usize)> = edge.iter().map(|&id| (angle(id), id)).collect();
        ring.sort_by(|a, b| a.0.total_cmp(&b.0));
        let n = ring.len();
        let mut parts: Vec<(f64, Vec<usize>)> = Vec::new();
        for i in 0..n {
            let span = (ring[(i + 1) % n].0 - ring[(i + n - 1) % n].0).rem_euclid(2.0 * PI);
            let kg = self.door_mass * 0.5 * span / (2.0 * PI);
            match parts.iter_mut().find(|(k, _)| (k - kg).abs() < 1e-9 * kg) {
                Some((_, ids)) => ids.push(ring[i].1),
                None => parts.push((kg, vec![ring[i].1])),
            }
        }
        for (j, (kg, ids)) in parts.into_iter().enumerate() {
            let name = if j == 0 {
                "CAB_DOOR".to_string()
            } else {
                format!("CAB_DOOR_{}", j + 1)
            };
            m.part(&name, Section::Mass { kg }).elements = ids.iter().map(|&id| vec![id]).collect();
        }
    }

    pub fn mesh(&self) -> Mesh {
        let mut m = Mesh::new(
            "washdyn cabinet: S8R panels and worktop, B32 frame and base, masses, feet springs",
        );
        let sheet = Section::Shell {
            thickness: self.sheet,
            material: steel(),
        };
        self.panels(&mut m, &sheet);
        let edge = self.front(&mut m, &sheet);
        m.add_to_set("GASKET", &edge);
        self.door(&mut m, &edge);
        self.frame(&mut m);
        self.base(&mut m);
        self.brackets(&mut m);
        self.masses(&mut m);
        self.feet(&mut m);
        m
    }

    /// The sides (y = +-half), the worktop and the back (x = -half); the sides and the back
    /// crowned outwards.
    fn panels(&self, m: &mut Mesh, sheet: &Section) {
        let (a, h, na, nz) = (self.half, self.height, self.n_across, self.n_up);
        let s = |u: f64| -a + 2.0 * a * u;
        // Sides y = +-a, bulging outwards (a sine-sine bump).
        for side in [-1.0, 1.0] {
            shell_grid(m, "CAB_SIDE", sheet, na, nz, false, |u, v| {
                let b = self.bulge * (PI * u).sin() * (PI * v).sin();
                [s(u), side * (a + b), h * v]
            });
        }
        let top = Section::Shell {
            thickness: self.worktop_thickness(),
            material: self.worktop.clone(),
        };
        shell_grid(m, "CAB_TOP", &top, na, na, false, |u, v| [s(u), s(v), h]);
        // The back bulges outwards too (a sheet pressed with a shallow crown).
        shell_grid(m, "CAB_BACK", sheet, na, nz, false, |u, v| {
            let b = self.back_bulge * (PI * u).sin() * (PI * v).sin();
            [-a - b, s(u), h * v]
        });
    }

    /// The 12 edges (posts, top and base frame) and the top rails under the springs.
    fn frame(&self, m: &mut Mesh) {
        let (a, h, na, nz) = (self.half, self.height, self.n_across, self.n_up);
        let frame = self.edge.section("STEEL_EDGE", [0.0, 0.0, 1.0]);
        let vertical = self.edge.section("STEEL_EDGE", [1.0, 0.0, 0.0]);
        for (x, y) in [(-a, -a), (-a, a), (a, -a), (a, a)] {
            beam_line(m, "CAB_POSTS", &vertical, [x, y, 0.0], [x, y, h], nz);
        }
        for z in [0.0, h] {
            for y in [-a, a] {
                beam_line(m, "CAB_FRAME", &frame, [-a, y, z], [a, y, z], na);
            }
            for x in [-a, a] {
                beam_line(m, "CAB_FRAME", &frame, [x, -a, z], [x, a, z], na);
            }
        }
        // Top rails across under the springs' cabinet ends (x = -0.10 and 0.12): the spring
        // loads go into the frame, not into the worktop alone.
        let rail = Section::Beam {
            width: self.rail_depth,
            height: self.rail_thickness,
            normal: [0.0, 0.0, 1.0],
            material: steel(),
        };
        for x in [-0.10, 0.12] {
            beam_line(m, "CAB_RAILS", &rail, [x, -a, h], [x, a, h], na);
        }
    }

    /// The base frame: rails along x under the dampers (y = +-damper_rail) and along y under
    /// the feet (x = +-foot), crossing at shared nodes.
    fn base(&self, m: &mut Mesh) {
        let (a, na) = (self.half, self.n_across);
        let base = Section::Beam {
            width: self.base_rail_depth,
            height: self.base_rail_width,
            normal: [0.0, 0.0, 1.0],
            material: steel(),
        };
        for y in [-self.damper_rail, self.damper_rail] {
            beam_line(m, "CAB_BASE", &base, [-a, y, 0.0], [a, y, 0.0], na);
        }
        let f = self.foot;
        for x in [-f, f] {
            beam_line(m, "CAB_BASE", &base, [x, -a, 0.0], [x, a, 0.0], na);
        }
    }

    /// The damper brackets: a stiff stub from the base rail up and out to the damper's end.
    /// The node set is the stub and its rail nodes within one node spacing: a local, stiff
    /// patch that the rigid fit reads as a translation and a rotation.
    fn brackets(&self, m: &mut Mesh) {
        let bracket = Section::Beam {
            width: self.bracket,
            height: self.bracket,
            normal: [1.0, 0.0, 0.0],
            material: steel(),
        };
        let spacing = 2.0 * self.half / (2 * self.n_across) as f64;
        for (k, p) in self.damper_points().iter().enumerate() {
            let foot_of = [p[0], p[1].signum() * self.damper_rail, 0.0];
            let stub = beam_line(m, "CAB_BRACKETS", &bracket, foot_of, *p, 1);
            let on_rail: Vec<usize> = (1..=m.nodes.len())
                .filter(|&id| {
                    let q = m.nodes[id - 1];
                    (q[1] - foot_of[1]).abs() < 1e-9
                        && q[2].abs() < 1e-9
                        && (q[0] - foot_of[0]).abs() <= spacing + 1e-9
                })
                .collect();
            m.add_to_set(&format!("DAMPER_{}", k + 1), &stub);
            m.add_to_set(&format!("DAMPER_{}", k + 1), &on_rail);
        }
    }

    /// Pump, valves and electronics: point masses on the base and frame nodes near them (the
    /// nearest such node if none lies within the part's radius).
    fn masses(&self, m: &mut Mesh) {
        let carriers: Vec<usize> = {
            let mut v: Vec<usize> = m
                .parts
                .iter()
                .filter(|p| ["CAB_BASE", "CAB_FRAME"].contains(&p.name.as_str()))
                .flat_map(|p| p.elements.iter().flatten().copied())
                .collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        for c in &self.carried {
            let mut ids = near(m, carriers.iter().copied(), c.at, c.radius);
            if ids.is_empty() {
                ids = vec![m.nearest(c.at, Some(&carriers))];
            }
            m.part(
                c.name,
                Section::Mass {
                    kg: c.kg / ids.len() as f64,
                },
            )
            .elements = ids.iter().map(|&id| vec![id]).collect();
        }
    }

    /// The feet: springs to the ground in x, y and z at each foot node (FOOT_1..4), which must
    /// be a base rail node.
    fn feet(&self, m: &mut Mesh) {
        let f = self.foot;
        let mut feet = Vec::new();
        for (k, (x, y)) in [(f, f), (f, -f), (-f, f), (-f, -f)].iter().enumerate() {
            let known = m.nodes.len();
            let id = m.node([*x, *y, 0.0]);
            assert_eq!(m.nodes.len(), known, "foot ({x}, {y}) is no base rail node");
            m.add_to_set(&format!("FOOT_{}", k + 1), &[id]);
            feet.push(id);
        }
        for (dof, k, name) in [
            (1, self.k_horizontal, "CAB_FOOT_X"),
            (2, self.k_horizontal, "CAB_FOOT_Y"),
            (3, self.k_vertical, "CAB_FOOT_Z"),
        ] {
            m.part(name, Section::Ground { dof, k }).elements =
                feet.iter().map(|&id| vec![id]).collect();
        }
    }
}
