//! The reference machine declared with `machine!`: the same numbers as `data/reference.toml`
//! (a test holds the two equal). Sources: docs/reference-machine.md; "estimate" there means an
//! engineering estimate, not a measurement.

washdyn_macros::machine! {
    /// The washdyn reference machine: a front loader of the seed paper's layout (Wagner &
    /// Pfeiffer, DETC99/VIB-8213). Frame: origin at the centre of the cabinet's base, x along
    /// the drum axis towards the door, y to the left seen from the front, z up. SI units. The
    /// cabinet is rigid and fixed until elastic bodies arrive.
    reference {
        gravity: [0.0, 0.0, -9.81],
        // The suspension's spring rates, the damper friction and the counterweights' bolt
        // torques are free parameters: the generated code takes them as inputs, so a study of
        // them (a loose bolt: torque 0) runs on this build.
        free: [
            "springs.spring_rear_left.stiffness",
            "springs.spring_rear_right.stiffness",
            "springs.spring_front.stiffness",
            "friction_dampers.damper_front_left.f_max",
            "friction_dampers.damper_front_right.f_max",
            "friction_dampers.damper_rear_left.f_max",
            "friction_dampers.damper_rear_right.f_max",
            "bolted_joints.bolt_top_1.torque.moment",
            "bolted_joints.bolt_top_2.torque.moment",
            "bolted_joints.bolt_top_3.torque.moment",
            "bolted_joints.bolt_top_4.torque.moment",
            "bolted_joints.bolt_bottom_1.torque.moment",
            "bolted_joints.bolt_bottom_2.torque.moment",
            "bolted_joints.bolt_bottom_3.torque.moment",
            "bolted_joints.bolt_bottom_4.torque.moment",
            "bolted_joints.bolt_collar_1.torque.moment",
            "bolted_joints.bolt_collar_2.torque.moment",
            "bolted_joints.bolt_collar_3.torque.moment",
            "bolted_joints.bolt_collar_4.torque.moment",
        ],

        // Suspended body: tub assembly with counterweight, bearing unit, motor stator, plus the
        // (non-spinning) mass of drum and motor rotor. ~60 kg in a comparable machine (Tuerkay
        // 1995). Mass, CoG and inertia: those of the FE models (tub 43.97 kg with its
        // counterweights, drum 9.52 kg, rotor 1.5 kg: 54.99 kg, CoG (-0.0001, 0, 0.450),
        // `washdyn fe modal`), which replaced the first estimate diag(2.6, 2.3, 2.3).
        tub {
            mass: 55.0,
            cog: [0.0, 0.0, 0.45],
            inertia: [[3.263, 0.0, -0.323], [0.0, 3.129, 0.0], [-0.323, 0.0, 2.74]],
        }

        // Drum: radius 0.24 m, depth 0.30 m, front face at x = +0.17; polar inertia of its FE
        // model (9.52 kg: shell, cast spider and hub, shaft, pulley; the first estimate, 0.49,
        // put all the mass on the shell). Only its spin acts here; its mass is part of the
        // tub's 55 kg.
        rotor drum {
            axis_point: [0.0, 0.0, 0.45],
            axis: [1.0, 0.0, 0.0],
            ratio: 1.0,
            polar_inertia: 0.232,
            // On the elastic tub the drum hangs on the tub's bearing (node set BEARING).
            mount: [-0.25, 0.0, 0.45],
        }

        // Motor rotor: belt ratio 11.25 (seed paper); polar inertia estimate; 1.5 kg
        // (estimate), which the elastic tub carries at its node set MOTOR.
        rotor motor {
            axis_point: [-0.05, 0.0, 0.18],
            axis: [1.0, 0.0, 0.0],
            ratio: 11.25,
            polar_inertia: 6.8e-4,
            mass: 1.5,
        }

        // Test unbalance: the seed paper's 0.6 kg magnet at the front position (radius 0.24 m,
        // x = +0.15), along +z at drum angle 0.
        unbalance test_mass { rotor: drum, mass: 0.6, position: [0.15, 0.0, 0.69] }

        // Motor unbalance 6e-6 kg m (balance grade G 6.3 for a 1.5 kg rotor at 15 750 rpm,
        // estimate), placed as 1.5e-4 kg at 0.04 m.
        unbalance motor_residual { rotor: motor, mass: 1.5e-4, position: [-0.05, 0.0, 0.22] }

        // Stationary run-up: 0 -> 93 rpm in 5 s, hold to 15 s, then 8 rpm/s to 1400 rpm
        // (estimate).
        speed { table: [[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]] }

        // Three vertical springs, 4000 N/m (4 x 3099 N/m in Tuerkay 1995); free lengths chosen so
        // that the 55 kg body hangs at rest with its CoG at (0, 0, 0.45): preloads 147.15,
        // 147.15, 245.25 N, free_length = 0.2 m - preload / k.
        spring spring_rear_left {
            a: { body: tub, point: [-0.10, 0.15, 0.62] },
            b: { body: cabinet, point: [-0.10, 0.15, 0.82] },
            stiffness: 4000.0,
            free_length: 0.1632125,
        }
        spring spring_rear_right {
            a: { body: tub, point: [-0.10, -0.15, 0.62] },
            b: { body: cabinet, point: [-0.10, -0.15, 0.82] },
            stiffness: 4000.0,
            free_length: 0.1632125,
        }
        spring spring_front {
            a: { body: tub, point: [0.12, 0.0, 0.62] },
            b: { body: cabinet, point: [0.12, 0.0, 0.82] },
            stiffness: 4000.0,
            free_length: 0.1386875,
        }

        // Four friction dampers, Fmax = 75 N each (300 N in all, against 2 x 100 N in a
        // production machine, Spelta et al. 2008: estimate); slope 2000 s/m (estimate: 90 % of
        // Fmax at 3.2 mm/s). Tub lugs DAMPER_1..4 at (+-0.18, +-0.18, 0.20), fore and aft of the
        // CoG, so pitch and yaw stroke them; cabinet ends DAMPER_1..4 at (+-0.18, +-0.27, 0.03),
        // 28 deg outwards from vertical, so lateral and roll motions stroke them too (`washdyn
        // modes`: every rigid mode strokes a damper by at least 0.17 mm per mm of door-ring
        // motion; the two dampers at x = 0 left one at 0.006). Rubber bushings 20 N m/rad, the
        // low end of 20-40 (Tuerkay 1995 quotes 80 for strut mounts): below ~300 rpm the dampers
        // stick, and four stuck dampers leave a roll about the x axis at z = 0.54 m (3.2 Hz,
        // where the left and right dampers' lines cross) to the bushings alone; 0.2 N m s/rad,
        // rubber's loss factor ~0.2 at that roll: 0.2 x 20 / (2 pi 3.2 Hz) (estimate). Run-up
        // peaks (rigid, `full`): 0.022 rad; 0.029 rad with 0.05 N m s/rad; 0.032, 0.036 rad with
        // 30, 40 N m/rad. The damper as built (law elasto_plastic, a scene's
        // `friction_law.elasto_plastic`): the two end bushings' axial stiffness in series,
        // 2 x 5e5 N/m in series = 2.5e5 N/m (the moving part's bearings': estimate).
        friction_damper damper_front_left {
            a: { body: tub, point: [0.18, 0.18, 0.20] },
            b: { body: cabinet, point: [0.18, 0.27, 0.03] },
            f_max: 75.0,
            slope: 2000.0,
            axial_stiffness: 2.5e5,
            bearing_stiffness: 20.0,
            bearing_damping: 0.2,
            moving_part: { mass: 0.55, inertia: 1.69e-3, translational_stiffness: 5.0e5 },
        }
        friction_damper damper_front_right {
            a: { body: tub, point: [0.18, -0.18, 0.20] },
            b: { body: cabinet, point: [0.18, -0.27, 0.03] },
            f_max: 75.0,
            slope: 2000.0,
            axial_stiffness: 2.5e5,
            bearing_stiffness: 20.0,
            bearing_damping: 0.2,
            moving_part: { mass: 0.55, inertia: 1.69e-3, translational_stiffness: 5.0e5 },
        }
        friction_damper damper_rear_left {
            a: { body: tub, point: [-0.18, 0.18, 0.20] },
            b: { body: cabinet, point: [-0.18, 0.27, 0.03] },
            f_max: 75.0,
            slope: 2000.0,
            axial_stiffness: 2.5e5,
            bearing_stiffness: 20.0,
            bearing_damping: 0.2,
            moving_part: { mass: 0.55, inertia: 1.69e-3, translational_stiffness: 5.0e5 },
        }
        friction_damper damper_rear_right {
            a: { body: tub, point: [-0.18, -0.18, 0.20] },
            b: { body: cabinet, point: [-0.18, -0.27, 0.03] },
            f_max: 75.0,
            slope: 2000.0,
            axial_stiffness: 2.5e5,
            bearing_stiffness: 20.0,
            bearing_damping: 0.2,
            moving_part: { mass: 0.55, inertia: 1.69e-3, translational_stiffness: 5.0e5 },
        }

        // Door gasket (estimate): a bellows, soft axially, stiffer radially, non-diagonal as the
        // seed paper states. Order (x, y, z, rx, ry, rz), global axes at the gasket point.
        // Damping hysteretic: rubber bellows have a loss factor of about 0.2, nearly independent
        // of frequency (estimate; the earlier viscous D = 0.01 s K gave 0.28 at 4.5 Hz and 1.46
        // at 23 Hz); in the time domain the equivalent viscous 0.2 K / max(|Omega|, 2 pi rad/s)
        // at the drum speed Omega (elements/gasket.rs).
        gasket door_gasket {
            a: tub,
            b: cabinet,
            point: [0.30, 0.0, 0.45],
            stiffness: [
                [3000.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                [0.0, 8000.0, 0.0, 0.0, 0.0, 600.0],
                [0.0, 0.0, 8000.0, 0.0, -600.0, 0.0],
                [0.0, 0.0, 0.0, 150.0, 0.0, 0.0],
                [0.0, 0.0, -600.0, 0.0, 120.0, 0.0],
                [0.0, 600.0, 0.0, 0.0, 0.0, 120.0],
            ],
            loss_factor: 0.2,
        }

        // Tub-cabinet contacts (effect `contact`): the door ring (8 points at r 0.25 m about the
        // drum axis at the gasket's x, where the validity monitor watches it) against the
        // cabinet's front opening, radially outwards. Clearance 20 mm (estimate: the gasket's
        // bellows leaves 15-25 mm between the tub's front ring and the opening's drawn collar;
        // the run-ups of the 0.6 kg load reach 11.9-12.5 mm). The surface moves with the
        // cabinet's node set GASKET (the opening's edge, centre [0.30, 0, 0.45]). Stiffness
        // 4e6 N/m^1.5 (estimate: a plastic rim on a rubber bumper against the steel collar,
        // secant 1.8e5 N/m at 2 mm, 2.8e5 N/m at 5 mm), Hertz's exponent 1.5, Hunt-Crossley
        // alpha 1.0 s/m (estimate: e = 0.66 at 0.5 m/s by the exact relation in
        // model/src/elements/contact.rs, a rubber bumper's 0.5-0.8). The tub's sides (r 0.27 m
        // against panels at 0.30 m: 30 mm) are not contacts: the door ring moves about 3 x as
        // far as the tub's centre (11.9 against 4.1 mm in `full`) with less clearance.
        contact door_ring_0 {
            a: tub, b: cabinet, point: [0.3, 0.0, 0.7],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, 0.0, 1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_1 {
            a: tub, b: cabinet, point: [0.3, 0.176776695296637, 0.626776695296637],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, 1.0, 1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_2 {
            a: tub, b: cabinet, point: [0.3, 0.25, 0.45],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, 1.0, 0.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_3 {
            a: tub, b: cabinet, point: [0.3, 0.176776695296637, 0.273223304703363],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, 1.0, -1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_4 {
            a: tub, b: cabinet, point: [0.3, 0.0, 0.2],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, 0.0, -1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_5 {
            a: tub, b: cabinet, point: [0.3, -0.176776695296637, 0.273223304703363],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, -1.0, -1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_6 {
            a: tub, b: cabinet, point: [0.3, -0.25, 0.45],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, -1.0, 0.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }
        contact door_ring_7 {
            a: tub, b: cabinet, point: [0.3, -0.176776695296637, 0.626776695296637],
            b_point: [0.3, 0.0, 0.45], normal: [0.0, -1.0, 1.0], gap: 0.02, stiffness: 4.0e6, alpha: 1.0,
        }

        // The tub's three concrete counterweights (issue 52), in the tub's 55 kg above; a scene
        // with `counterweights` makes each a rigid body on four bolts and takes its mass out of
        // the tub's. Mass properties: the FE tub's C3D20 sectors (docs/reference-machine.md).
        counterweight counterweight_top {
            mass: 10.7646,
            cog: [0.05, 0.0, 0.62872],
            inertia: [[0.50494, 0.0, 0.0], [0.0, 0.13222, 0.0], [0.0, 0.0, 0.47606]],
        }
        counterweight counterweight_bottom {
            mass: 8.3598,
            cog: [0.05, 0.0, 0.27278],
            inertia: [[0.38548, 0.0, 0.0], [0.0, 0.10158, 0.0], [0.0, 0.0, 0.36415]],
        }
        counterweight counterweight_collar {
            mass: 5.8685,
            cog: [0.235, 0.0, 0.61655],
            inertia: [[0.23913, 0.0, 0.0], [0.0, 0.04644, 0.0], [0.0, 0.0, 0.20922]],
        }
        // Each on four M8 bolts through the tub wall, radial, 60 degrees either side of its
        // centre line; 15 N m on M8 gives 11.4 kN (VDI 2230 R13). Estimates:
        // docs/reference-machine.md.
        bolted_joint bolt_top_1 {
            counterweight: counterweight_top, point: [-0.04, -0.23383, 0.585], axis: [0.0, -0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_top_2 {
            counterweight: counterweight_top, point: [-0.04, 0.23383, 0.585], axis: [0.0, 0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_top_3 {
            counterweight: counterweight_top, point: [0.14, -0.23383, 0.585], axis: [0.0, -0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_top_4 {
            counterweight: counterweight_top, point: [0.14, 0.23383, 0.585], axis: [0.0, 0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_bottom_1 {
            counterweight: counterweight_bottom, point: [-0.04, 0.23383, 0.315], axis: [0.0, 0.86603, -0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_bottom_2 {
            counterweight: counterweight_bottom, point: [-0.04, -0.23383, 0.315], axis: [0.0, -0.86603, -0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_bottom_3 {
            counterweight: counterweight_bottom, point: [0.14, 0.23383, 0.315], axis: [0.0, 0.86603, -0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_bottom_4 {
            counterweight: counterweight_bottom, point: [0.14, -0.23383, 0.315], axis: [0.0, -0.86603, -0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_collar_1 {
            counterweight: counterweight_collar, point: [0.2025, -0.21651, 0.575], axis: [0.0, -0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_collar_2 {
            counterweight: counterweight_collar, point: [0.2025, 0.21651, 0.575], axis: [0.0, 0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_collar_3 {
            counterweight: counterweight_collar, point: [0.2675, -0.21651, 0.575], axis: [0.0, -0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }
        bolted_joint bolt_collar_4 {
            counterweight: counterweight_collar, point: [0.2675, 0.21651, 0.575], axis: [0.0, 0.86603, 0.5],
            torque: { moment: 15.0, pitch: 1.25e-3, pitch_diameter: 7.188e-3, thread_friction: 0.12, head_friction: 0.12, head_diameter: 10.3e-3 },
            bolt_stiffness: 1.9e8, member_stiffness: 7.6e8, shear_stiffness: 3.0e8, bolt_bending_stiffness: 4.1e6, interface_diameter: 0.033,
            friction: 0.3, damping: 2000.0,
        }

        // Measurement points after the seed paper's 5 + 2 (positions: estimate). cabinet2 is the
        // centre of the left side panel; both cabinet points read zero while the cabinet is rigid
        // and fixed.
        sensor tub1 { body: tub, point: [0.30, 0.0, 0.70], kind: acceleration }
        sensor tub2 { body: tub, point: [0.30, 0.25, 0.45], kind: acceleration }
        sensor tub3 { body: tub, point: [-0.25, 0.0, 0.70], kind: acceleration }
        sensor tub4 { body: tub, point: [0.0, 0.30, 0.45], kind: acceleration }
        sensor tub5 { body: tub, point: [-0.05, 0.0, 0.15], kind: acceleration }
        sensor cabinet1 { body: cabinet, point: [0.30, 0.30, 0.80], kind: acceleration }
        sensor cabinet2 { body: cabinet, point: [0.0, 0.30, 0.45], kind: acceleration }
        // Displacement of the drum's front centre: the point on the drum's axis that the drum's
        // frame carries (the tub's rigid motion, and on the elastic tub its motion at the
        // bearing).
        sensor drum_front { body: drum, point: [0.17, 0.0, 0.45], kind: displacement }

        // Each scene's default integration (`solver`), chosen by measuring the whole run-up
        // (docs/performance.md, issue 48).
        scene full {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia,
            ],
            solver: { method: dopri5, tol: 1e-6 },
        }
        // `full` with the dampers as built: the slider in series with the end bushings
        // (elasto-plastic presliding, issue 48).
        scene presliding {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, friction_law.elasto_plastic,
            ],
            solver: { method: dopri5, tol: 1e-6 },
        }
        scene rigid_low_speed {
            effects: [
                unbalance.drum, friction_dampers, gasket_damping, element_geometry,
                unbalance_inertia,
            ],
            solver: { method: dopri5, tol: 1e-6 },
        }

        // The seed paper's "two independent bodies": `full` with each damper's moving part as
        // a body of its own instead of the massless element.
        scene damper_mass {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, damper_mass.damper_front_left,
                damper_mass.damper_front_right, damper_mass.damper_rear_left,
                damper_mass.damper_rear_right,
            ],
            solver: { method: galpha, tol: 1e-6 },
        }

        // `full` with the counterweights as rigid bodies on their bolted joints (issue 52): the
        // seed paper's remedy for its missing even orders, on the rigid tub.
        scene counterweights {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, counterweights,
            ],
            solver: { method: galpha, tol: 1e-6 },
        }

        // `full` with the tub-cabinet contacts: the door ring knocks against the opening
        // instead of the validity monitor's warning.
        scene contact {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, contact,
            ],
            solver: { method: dopri5, tol: 1e-6 },
        }

        // Elastic bodies (issue 8's FE models, `washdyn fe modal`): the tub free-free on its 6
        // rigid DOF, the drum clamped at its bearing, the cabinet on its feet. Modal damping
        // 2 % (estimate).
        elastic tub { file: "fe/tub.modal.toml", bare: "fe/tub_bare.modal.toml", damping: 0.02 }
        elastic drum { file: "fe/drum.modal.toml", damping: 0.02 }
        // The cabinet's on-feet modes get 6 % by the feet's share of their strain energy
        // (rubber feet on a floor, 5-8 %: estimate).
        // The bulged side panels' characteristic curves on their fundamental modes (4 and 5,
        // 50.1 and 53.9 Hz), from ccx's nonlinear statics (issue 52; docs/even-orders.md).
        elastic cabinet {
            file: "fe/cabinet.modal.toml",
            damping: 0.02,
            support_damping: 0.06,
            curves: "fe/cabinet.curves.toml",
        }

        // The paper's elastic machine, its dampers as built (the slider in series with the end
        // bushings, `friction_law.elasto_plastic`: the arctan law's stuck dashpot tied the tub
        // to the brackets' kHz give, eigenvalues near -1.6e6 1/s; issue 48): everything above
        // with the tub's, the drum's and the cabinet's modes up to drum order 12 at top speed times 1.5 (420 Hz: 16 tub
        // eigenmodes; every mode of the drum's and the cabinet's data), the tub's dropped modes
        // folded into two Krylov blocks under every element load (359 coordinates). Chosen by
        // issue 21's cut study (docs/truncation.md): the cut at 210 Hz missed the 1400 rpm
        // steady state by 62 % and 0.98 dB; one block instead of two, by 1.3e-2 at 1100 rpm.
        scene elastic {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.tub, elastic.drum, elastic.cabinet,
                centrifugal_stiffening, friction_law.elasto_plastic,
            ],
            solver: { method: dopri5, tol: 1e-6 },
            max_order: 12.0,
        }

        // `elastic` with the tub's modes to 700 Hz (373 coordinates; docs/truncation.md).
        scene elastic_fine {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.tub, elastic.drum, elastic.cabinet,
                centrifugal_stiffening, friction_law.elasto_plastic,
            ],
            solver: { method: dopri5, tol: 1e-6 },
            max_order: 20.0,
        }

        // The same with the tub rigid: the drum's and the cabinet's modes. (With the elastic
        // tub the run-up meets the drum bouncing on the tub's bearing unit near 800 rpm and
        // stops at the small-motion bound; see docs/elastic-machine.md.)
        scene elastic_rigid_tub {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.drum, elastic.cabinet,
                centrifugal_stiffening, friction_law.elasto_plastic,
            ],
            solver: { method: dopri5, tol: 1e-6 },
            max_order: 12.0,
        }

        // `elastic_rigid_tub` with the side panels' characteristic curves: the bulge's stiffness
        // that differs between the two directions, the seed paper's remedy for its Figure 14
        // (the cabinet's speed plot not symmetric about zero) and a source of even orders.
        scene panel_curves {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.drum, elastic.cabinet,
                centrifugal_stiffening, friction_law.elasto_plastic, characteristic_curves.cabinet,
            ],
            solver: { method: dopri5, tol: 1e-6 },
            max_order: 12.0,
        }

        // `elastic_rigid_tub` with the counterweights on their bolted joints: the cabinet's
        // channels of the counterweights' even orders (docs/even-orders.md; loose bolts: a study
        // that sets the free torques to 0 runs on this build).
        scene cabinet_counterweights {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.drum, elastic.cabinet,
                centrifugal_stiffening, friction_law.elasto_plastic, counterweights,
            ],
            solver: { method: dopri5, tol: 1e-6 },
            max_order: 12.0,
        }
    }
}
