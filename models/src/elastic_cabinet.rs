//! The reference machine with its elastic cabinet: the rigid tub in the cabinet's FE modes.

washdyn_macros::machine! {
    /// The reference machine with the cabinet's first 20 modes (effect `elastic.cabinet`).
    elastic_cabinet {
        base: "data/reference.toml",
        elastic cabinet { file: "fe/cabinet.modal.toml", modes: 20, damping: 0.02 }
        scene elastic {
            effects: ["gyroscopic", "unbalance.drum", "unbalance.motor", "friction_dampers",
                      "gasket_damping", "element_geometry", "unbalance_inertia", "elastic.cabinet"],
        }
    }
}
