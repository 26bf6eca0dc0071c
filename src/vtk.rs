//! VTK XML unstructured grids (`.vtu`, appended raw binary, little endian, UInt64 headers) and
//! `.pvd` collections for ParaView. Written here rather than with vtkio: its only releases since
//! 2021 are release candidates, and its default features build C compression libraries; what we
//! write is one grid layout with point and cell data, about a page of code.

use std::io::Write;
use std::path::Path;

use crate::error::FileError;
pub use crate::error::vtk::VtkError;

impl VtkError {
    fn io(path: &Path) -> impl Fn(std::io::Error) -> VtkError + Copy + '_ {
        move |source| {
            VtkError::Io(FileError {
                path: path.to_path_buf(),
                source,
            })
        }
    }
}

/// One cell: VTK type and 0-based point indices in VTK order.
pub struct Cell<'a> {
    pub vtk: u8,
    pub nodes: &'a [u32],
}

/// Data on points or cells: name (with its unit), components (1, 3 or 6), values.
pub struct Data<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: &'a [f64],
}

/// Write an unstructured grid.
pub fn write_vtu(
    path: &Path,
    points: &[[f64; 3]],
    cells: &[Cell],
    point_data: &[Data],
    cell_data: &[Data],
) -> Result<u64, VtkError> {
    let err = VtkError::io(path);
    let mut blocks: Vec<Vec<u8>> = Vec::new();
    let mut xml = String::new();
    let mut offset = 0u64;
    let mut array = |xml: &mut String, attrs: String, bytes: Vec<u8>| {
        xml.push_str(&format!(
            "        <DataArray {attrs} format=\"appended\" offset=\"{offset}\"/>\n"
        ));
        offset += 8 + bytes.len() as u64;
        blocks.push(bytes);
    };
    let f64s =
        |v: &mut dyn Iterator<Item = f64>| -> Vec<u8> { v.flat_map(|x| x.to_le_bytes()).collect() };
    // Data as Float32 (7 digits: a picture's and a plot's needs; half the size of a run-up's
    // series), points as Float64 (exact rest positions), indices as Int32.
    let f32s = |v: &mut dyn Iterator<Item = f64>| -> Vec<u8> {
        v.flat_map(|x| (x as f32).to_le_bytes()).collect()
    };
    xml.push_str(&format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    \
         <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n      <Points>\n",
        points.len(),
        cells.len()
    ));
    array(
        &mut xml,
        "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"".into(),
        f64s(&mut points.iter().flatten().copied()),
    );
    xml.push_str("      </Points>\n      <Cells>\n");
    let conn: Vec<u8> = cells
        .iter()
        .flat_map(|c| c.nodes.iter())
        .flat_map(|&i| (i as i32).to_le_bytes())
        .collect();
    array(
        &mut xml,
        "type=\"Int32\" Name=\"connectivity\"".into(),
        conn,
    );
    let mut end = 0i32;
    let offs: Vec<u8> = cells
        .iter()
        .flat_map(|c| {
            end += c.nodes.len() as i32;
            end.to_le_bytes()
        })
        .collect();
    array(&mut xml, "type=\"Int32\" Name=\"offsets\"".into(), offs);
    array(
        &mut xml,
        "type=\"UInt8\" Name=\"types\"".into(),
        cells.iter().map(|c| c.vtk).collect(),
    );
    xml.push_str("      </Cells>\n");
    for (tag, data, count) in [
        ("PointData", point_data, points.len()),
        ("CellData", cell_data, cells.len()),
    ] {
        xml.push_str(&format!("      <{tag}>\n"));
        for d in data {
            if d.values.len() != d.components * count {
                return Err(VtkError::Length {
                    path: path.to_path_buf(),
                    name: d.name.to_string(),
                    values: d.values.len(),
                    count,
                    components: d.components,
                });
            }
            array(
                &mut xml,
                format!(
                    "type=\"Float32\" Name=\"{}\" NumberOfComponents=\"{}\"",
                    d.name, d.components
                ),
                f32s(&mut d.values.iter().copied()),
            );
        }
        xml.push_str(&format!("      </{tag}>\n"));
    }
    xml.push_str("    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_");
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
    f.write_all(xml.as_bytes()).map_err(err)?;
    for b in &blocks {
        f.write_all(&(b.len() as u64).to_le_bytes()).map_err(err)?;
        f.write_all(b).map_err(err)?;
    }
    f.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
        .map_err(err)?;
    f.flush().map_err(err)?;
    Ok(std::fs::metadata(path).map_err(err)?.len())
}

/// A `.pvd` collection: (time s, file relative to the collection) per step.
pub fn write_pvd(path: &Path, steps: &[(f64, String)]) -> Result<(), VtkError> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n",
    );
    for (t, file) in steps {
        s.push_str(&format!(
            "    <DataSet timestep=\"{t}\" part=\"0\" file=\"{file}\"/>\n"
        ));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    std::fs::write(path, s).map_err(VtkError::io(path))
}
