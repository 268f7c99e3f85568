//! 3MF (3D Manufacturing Format), the package slicers such as PrusaSlicer, Cura and Bambu
//! Studio prefer for printing: a zip archive (natively the `zip` crate's, in the browser
//! [`super::zip_archive`]'s) holding one object's mesh in the 3MF core XML.
//!
//! The model part is `/3D/3dmodel.model`, the name the specification's examples use and the
//! one slicers look for; the XML has three element kinds, written here directly.

use super::mesh::WorldMesh;
use crate::xml::escape;
use std::fmt::Write as _;

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
 <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
 <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>
"#;

const RELATIONSHIPS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"#;

/// `mesh` as a 3MF package with one object and one build item. Coordinates are written as
/// they are (shortest round-trip decimals); 3MF reads them as millimetres, so a surface in
/// metres prints at 1:1000 unless the slicer scales it. `name` labels the object.
pub fn to_3mf(mesh: &WorldMesh, name: &str) -> Result<Vec<u8>, String> {
    #[cfg(not(target_arch = "wasm32"))]
    return with_zip_crate(&model(mesh, name));
    #[cfg(target_arch = "wasm32")]
    return to_3mf_deflated(mesh, name);
}

/// [`to_3mf`] packed by `super::zip_archive::deflated_zip`, as the browser build writes it.
pub fn to_3mf_deflated(mesh: &WorldMesh, name: &str) -> Result<Vec<u8>, String> {
    let xml = model(mesh, name);
    super::zip_archive::deflated_zip(&[
        ("[Content_Types].xml", CONTENT_TYPES.as_bytes()),
        ("_rels/.rels", RELATIONSHIPS.as_bytes()),
        ("3D/3dmodel.model", xml.as_bytes()),
    ])
}

/// The model part's XML: one object with `mesh`, and one build item.
fn model(mesh: &WorldMesh, name: &str) -> String {
    let mut xml = String::with_capacity(64 * (mesh.vertices.len() + mesh.triangles.len()) + 512);
    xml.push_str(concat!(
        r#"<?xml version="1.0" encoding="UTF-8"?>"#,
        "\n",
        r#"<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">"#,
        "\n <resources>\n"
    ));
    let _ = writeln!(
        xml,
        r#"  <object id="1" type="model" name="{}">"#,
        escape(name)
    );
    xml.push_str("   <mesh>\n    <vertices>\n");
    for [x, y, z] in &mesh.vertices {
        let _ = writeln!(xml, r#"     <vertex x="{x}" y="{y}" z="{z}"/>"#);
    }
    xml.push_str("    </vertices>\n    <triangles>\n");
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(xml, r#"     <triangle v1="{a}" v2="{b}" v3="{c}"/>"#);
    }
    xml.push_str(concat!(
        "    </triangles>\n   </mesh>\n  </object>\n </resources>\n",
        " <build>\n  <item objectid=\"1\"/>\n </build>\n</model>\n"
    ));
    xml
}

#[cfg(not(target_arch = "wasm32"))]
fn with_zip_crate(xml: &str) -> Result<Vec<u8>, String> {
    use std::io::{Cursor, Write};
    use zip::ZipWriter;
    use zip::write::SimpleFileOptions;
    let fail = |e: &dyn std::fmt::Display| format!("cannot write the 3MF package: {e}");
    let mut archive = ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for (part, text) in [
        ("[Content_Types].xml", CONTENT_TYPES),
        ("_rels/.rels", RELATIONSHIPS),
        ("3D/3dmodel.model", xml),
    ] {
        archive.start_file(part, options).map_err(|e| fail(&e))?;
        archive.write_all(text.as_bytes()).map_err(|e| fail(&e))?;
    }
    let out = archive.finish().map_err(|e| fail(&e))?;
    Ok(out.into_inner())
}
