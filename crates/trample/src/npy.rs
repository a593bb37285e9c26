//! NumPy `.npy` files (format version 1.0): the dumps of `trample simulate`
//! and `trample collide`. Written to a temporary name and renamed, so a
//! failed run never leaves a half-written file.

use std::io::Write;
use std::path::Path;

/// Element types the dumps use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// Little-endian float32 (`<f4`).
    F32,
    /// uint8 (`|u1`).
    U8,
}

impl Dtype {
    fn descr(self) -> &'static str {
        match self {
            Dtype::F32 => "<f4",
            Dtype::U8 => "|u1",
        }
    }
}

/// The bytes of a `.npy` file holding `data` (already in little-endian
/// element order) with C-order `shape`.
#[must_use]
pub fn encode(dtype: Dtype, shape: &[usize], data: &[u8]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let shape_txt = if shape.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut header = format!(
        "{{'descr': '{}', 'fortran_order': False, 'shape': {}, }}",
        dtype.descr(),
        shape_txt
    );
    // Magic (6) + version (2) + header length (2) + header + '\n' is a multiple of 64.
    let total = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - total % 64) % 64));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

/// Writes float32 values with `shape` to `path` atomically.
pub fn write_f32(path: &Path, shape: &[usize], values: &[f32]) -> std::io::Result<()> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    write_atomic(path, &encode(Dtype::F32, shape, &bytes))
}

/// Writes uint8 values with `shape` to `path` atomically.
pub fn write_u8(path: &Path, shape: &[usize], values: &[u8]) -> std::io::Result<()> {
    write_atomic(path, &encode(Dtype::U8, shape, values))
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A decoded `.npy` file (for tests and tools).
#[derive(Clone, Debug, PartialEq)]
pub struct NpyArray {
    /// Element type.
    pub dtype: Dtype,
    /// C-order shape.
    pub shape: Vec<usize>,
    /// Raw little-endian element bytes.
    pub data: Vec<u8>,
}

impl NpyArray {
    /// The elements as f32 (dtype must be F32).
    #[must_use]
    pub fn to_f32(&self) -> Vec<f32> {
        self.data
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }
}

/// Parses a `.npy` file written by this module.
pub fn decode(bytes: &[u8]) -> Result<NpyArray, String> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err("not a .npy file (bad magic)".into());
    }
    let hlen = usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
    let header = std::str::from_utf8(bytes.get(10..10 + hlen).ok_or("truncated header")?)
        .map_err(|_| "header is not UTF-8")?;
    let dtype = if header.contains("'<f4'") {
        Dtype::F32
    } else if header.contains("'|u1'") {
        Dtype::U8
    } else {
        return Err(format!("unsupported dtype in header {header}"));
    };
    let open = header.find("'shape': (").ok_or("no shape")? + 10;
    let close = open + header[open..].find(')').ok_or("bad shape")?;
    let shape: Vec<usize> = header[open..close]
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().map_err(|_| format!("bad dimension {s}")))
        .collect::<Result<_, _>>()?;
    let data = bytes[10 + hlen..].to_vec();
    let elem = if dtype == Dtype::F32 { 4 } else { 1 };
    if data.len() != shape.iter().product::<usize>() * elem {
        return Err("data length does not match the shape".into());
    }
    Ok(NpyArray { dtype, shape, data })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_aligned_and_round_trips() {
        let bytes = encode(Dtype::F32, &[2, 3], &[0u8; 24]);
        let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + hlen) % 64, 0);
        assert_eq!(bytes[10 + hlen - 1], b'\n');
        let a = decode(&bytes).unwrap();
        assert_eq!(a.shape, vec![2, 3]);
        let one = decode(&encode(Dtype::U8, &[5], &[1, 2, 3, 4, 5])).unwrap();
        assert_eq!(one.shape, vec![5]);
        assert!(
            std::str::from_utf8(&encode(Dtype::U8, &[5], &[0; 5])[10..])
                .unwrap()
                .contains("(5,)")
        );
    }

    #[test]
    fn atomic_write_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("trample-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.npy");
        write_f32(&p, &[2], &[1.5, -2.0]).unwrap();
        assert_eq!(
            decode(&std::fs::read(&p).unwrap()).unwrap().to_f32(),
            vec![1.5, -2.0]
        );
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
