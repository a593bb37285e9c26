//! glTF and GLB fixtures written in code: one mesh of one primitive over
//! an embedded or external buffer.

/// The triangle used by the glTF fixtures, counter-clockwise seen from +z.
pub const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// Binary buffer: positions (VEC3 f32) then u16 indices, padded to 4 bytes.
pub fn buffer_bytes(positions: &[[f32; 3]], indices: &[u16]) -> Vec<u8> {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    while !bytes.len().is_multiple_of(4) {
        bytes.push(0);
    }
    bytes
}

/// A glTF document with one mesh of one primitive (`mode`) over
/// `vertex_count` positions and `index_count` u16 indices at the end of
/// buffer 0 (`uri`: `None` for a GLB's BIN chunk), placed by `nodes`.
pub fn document(
    uri: Option<&str>,
    buffer_length: usize,
    vertex_count: usize,
    index_count: usize,
    mode: u32,
    nodes: &str,
) -> String {
    let uri = uri
        .map(|u| format!(r#", "uri": "{u}""#))
        .unwrap_or_default();
    let positions_length = vertex_count * 12;
    format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "scene": 0,
  "scenes": [{{ "nodes": [0] }}],
  "nodes": {nodes},
  "meshes": [{{ "primitives": [{{ "attributes": {{ "POSITION": 0 }}, "indices": 1, "mode": {mode} }}] }}],
  "buffers": [{{ "byteLength": {buffer_length}{uri} }}],
  "bufferViews": [
    {{ "buffer": 0, "byteOffset": 0, "byteLength": {positions_length} }},
    {{ "buffer": 0, "byteOffset": {positions_length}, "byteLength": {index_length} }}
  ],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": {vertex_count}, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] }},
    {{ "bufferView": 1, "componentType": 5123, "count": {index_count}, "type": "SCALAR" }}
  ]
}}"#,
        index_length = index_count * 2,
    )
}

/// Standard base64 with padding (RFC 4648), for data uris.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            out.push(if i <= chunk.len() {
                ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    out
}

/// A GLB container: header, JSON chunk (space-padded), BIN chunk if any.
pub fn glb(json: &str, bin: Option<&[u8]>) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut body = Vec::new();
    body.extend((json.len() as u32).to_le_bytes());
    body.extend(b"JSON");
    body.extend(&json);
    if let Some(bin) = bin {
        body.extend((bin.len() as u32).to_le_bytes());
        body.extend(b"BIN\0");
        body.extend(bin);
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((12 + body.len() as u32).to_le_bytes());
    out.extend(body);
    out
}

/// The single-triangle glTF with an embedded buffer, placed by `nodes`.
pub fn embedded_triangle(nodes: &str) -> String {
    let bytes = buffer_bytes(&TRIANGLE, &[0, 1, 2]);
    let uri = format!("data:application/octet-stream;base64,{}", base64(&bytes));
    document(Some(&uri), bytes.len(), 3, 3, 4, nodes)
}
