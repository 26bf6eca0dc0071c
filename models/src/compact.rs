//! A compact machine as a variant of the reference file: only what differs is written.

washdyn_macros::machine! {
    /// The reference machine with a smaller drum and stiffer springs.
    compact {
        base: "data/reference.toml",

        // Drum radius 0.21 m instead of 0.24: a drum of the same depth and wall has polar
        // inertia ~ r^3, 0.232 * (0.21 / 0.24)^3 = 0.155 kg m^2 (estimate); the test mass sits
        // 0.21 m above the axis.
        rotor drum { polar_inertia: 0.155 }
        unbalance test_mass { position: [0.15, 0.0, 0.66] }

        // 5000 N/m springs; free_length = 0.2 m - preload / k keeps the CoG at rest at z = 0.45
        // (preloads 147.15, 147.15, 245.25 N as in the reference).
        spring spring_rear_left { stiffness: 5000.0, free_length: 0.17057 }
        spring spring_rear_right { stiffness: 5000.0, free_length: 0.17057 }
        spring spring_front { stiffness: 5000.0, free_length: 0.15095 }

        // A displacement sensor on the drum's front rim (DRUM_EDGE_0 at drum angle 0): it turns
        // with the drum, so the generated code reads it with the drive angle.
        sensor drum_rim { body: drum, point: [0.17, 0.0, 0.69], kind: displacement }

        // The FE models are the reference's tub and drum; the compact drum has none of its own,
        // so its elastic scenes keep tub and drum rigid and only the (shared) cabinet elastic.
        scene elastic {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.cabinet,
            ],
        }
        scene elastic_rigid_tub {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.cabinet,
            ],
        }
        scene elastic_fine {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.cabinet,
            ],
        }
        scene panel_curves {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.cabinet,
                characteristic_curves.cabinet,
            ],
        }
        scene cabinet_counterweights {
            effects: [
                gyroscopic, unbalance.drum, unbalance.motor, friction_dampers, gasket_damping,
                element_geometry, unbalance_inertia, elastic.cabinet, counterweights,
            ],
        }
    }
}
