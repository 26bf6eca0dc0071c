use washdyn_runtime::codegen::trace_equations;
use washdyn_runtime::equations::Equations;
use washdyn_runtime::symbolic::Node;
fn main() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/reference.toml");
    let m = washdyn_runtime::ir::toml_file::load_file(&path).expect("reference model");
    let eff = m.scene(Some("elastic")).unwrap();
    let eq = Equations::new(&m, &eff);
    let (g, m1, h) = &trace_equations(&eq).mh;
    for (name, outs) in [("m1", m1), ("h", h)] {
        let live = g.live(outs);
        let mut scalar = 0;
        let mut mv = 0;
        let mut mvflops = 0;
        for (i, l) in live.iter().enumerate() {
            if !l {
                continue;
            }
            match g.nodes[i] {
                Node::Const(_) | Node::Input(_) | Node::Pick(..) => {}
                Node::MatVec { table, .. } => {
                    mv += 1;
                    mvflops += 2 * g.tables[table as usize].len()
                }
                _ => scalar += 1,
            }
        }
        println!("{name}: scalar {scalar} matvec {mv} flops {mvflops}");
    }
    println!("n1 {} n {}", eq.layout.n1, eq.layout.n());
}
