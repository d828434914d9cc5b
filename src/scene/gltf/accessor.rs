//! Reading accessors with every range checked: a file whose accessors, buffer views or sparse
//! substitutions point outside their buffers is an error naming them, never a panic.
//!
//! An accessor is `count` elements of `N` components; element i starts at
//! view.byteOffset + accessor.byteOffset + i·stride (stride = byteStride or the element size).
//! Sparse accessors start from their buffer view (or zeros) and replace the listed elements.

use ::gltf::accessor::{Accessor, DataType, Dimensions};

use crate::error::InputResult;
use crate::scene::gltf::document::GltfDocument;

/// Reads `accessor` as `N`-component f32 vectors. `types` lists the component types accepted
/// (besides the element shape); integer types convert as normalised when the accessor says so.
pub fn read_vectors<const N: usize>(
    d: &GltfDocument,
    accessor: &Accessor,
    what: &str,
    types: &[DataType],
) -> InputResult<Vec<[f32; N]>> {
    check_type(d, accessor, what, N, types)?;
    let (ty, normalized) = (accessor.data_type(), accessor.normalized());
    let size = ty.size();
    let access = check_access(d, accessor, what)?;
    let mut out = vec![[0.0; N]; access.count];
    access.for_each(|i, bytes| {
        out[i] = std::array::from_fn(|c| component(&bytes[c * size..(c + 1) * size], ty, normalized));
    });
    Ok(out)
}

/// Reads an index accessor (unsigned byte, short or int scalars).
pub fn read_indices(d: &GltfDocument, accessor: &Accessor, what: &str) -> InputResult<Vec<u32>> {
    check_type(d, accessor, what, 1, &[DataType::U8, DataType::U16, DataType::U32])?;
    let ty = accessor.data_type();
    let access = check_access(d, accessor, what)?;
    let mut out = vec![0u32; access.count];
    access.for_each(|i, bytes| out[i] = unsigned(bytes, ty));
    Ok(out)
}

fn check_type(d: &GltfDocument, a: &Accessor, what: &str, n: usize, types: &[DataType]) -> InputResult<()> {
    let dims = a.dimensions();
    let shape_ok = match dims {
        Dimensions::Scalar => n == 1,
        Dimensions::Vec2 => n == 2,
        Dimensions::Vec3 => n == 3,
        Dimensions::Vec4 => n == 4,
        _ => false,
    };
    if !shape_ok || !types.contains(&a.data_type()) {
        return Err(d.error(format!(
            "accessor {} ({what}) is {dims:?} of {:?}, expected {n} component(s) of {types:?}",
            a.index(),
            a.data_type()
        )));
    }
    Ok(())
}

/// An accessor whose every byte has been checked to lie in its buffer view, and every view in
/// its buffer, before anything is allocated for its elements.
struct CheckedAccess<'d> {
    count: usize,
    size: usize,
    /// (view bytes from the accessor's offset, stride), or `None`: the base values are zeros.
    base: Option<(&'d [u8], usize)>,
    /// Sparse substitutions: (index bytes, index type, value bytes).
    sparse: Option<(&'d [u8], DataType, &'d [u8])>,
}

fn check_access<'d>(d: &'d GltfDocument, a: &Accessor, what: &str) -> InputResult<CheckedAccess<'d>> {
    let (count, size) = (a.count(), a.size());
    let err = |problem: String| d.error(format!("accessor {} ({what}): {problem}", a.index()));
    let mut access = CheckedAccess {
        count,
        size,
        base: None,
        sparse: None,
    };
    if count == 0 {
        return Ok(access);
    }
    if let Some(view) = a.view() {
        let data = view_bytes(d, &view).map_err(err)?;
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(err(format!(
                "byteStride {stride} is smaller than the element size {size}"
            )));
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|v| v.checked_add(size))
            .and_then(|v| v.checked_add(a.offset()));
        match end {
            Some(end) if end <= data.len() => access.base = Some((&data[a.offset()..end], stride)),
            _ => {
                return Err(err(format!(
                    "{count} elements of {size} bytes (stride {stride}) from offset {} run past the end of buffer view {} ({} bytes)",
                    a.offset(),
                    view.index(),
                    data.len()
                )))
            }
        }
    }
    if let Some(sparse) = a.sparse() {
        let n = sparse.count();
        let json = &d.doc.as_json().accessors[a.index()];
        let index_type = match json.sparse.as_ref().map(|s| &s.indices.component_type) {
            Some(::gltf::json::validation::Checked::Valid(t)) => t.0,
            _ => return Err(err("sparse indices have no valid component type".into())),
        };
        if !matches!(index_type, DataType::U8 | DataType::U16 | DataType::U32) {
            return Err(err(format!(
                "sparse indices of type {index_type:?} (expected unsigned)"
            )));
        }
        let (indices, values) = (sparse.indices(), sparse.values());
        let index_bytes = view_range(d, &indices.view(), indices.offset(), index_type.size(), n).map_err(err)?;
        let value_bytes = view_range(d, &values.view(), values.offset(), size, n).map_err(err)?;
        for k in 0..n {
            let i = unsigned(&index_bytes[k * index_type.size()..], index_type) as usize;
            if i >= count {
                return Err(err(format!("sparse index {i} is out of range ({count} elements)")));
            }
        }
        access.sparse = Some((index_bytes, index_type, value_bytes));
    }
    Ok(access)
}

impl CheckedAccess<'_> {
    /// Calls `f(i, bytes)` for every element i (sparse substitutions after the base values, so
    /// they win).
    fn for_each(&self, mut f: impl FnMut(usize, &[u8])) {
        let size = self.size;
        match self.base {
            Some((data, stride)) => {
                for i in 0..self.count {
                    f(i, &data[i * stride..i * stride + size]);
                }
            }
            None => {
                let zeros = vec![0u8; size];
                for i in 0..self.count {
                    f(i, &zeros);
                }
            }
        }
        if let Some((indices, index_type, values)) = self.sparse {
            let index_size = index_type.size();
            for k in 0..indices.len() / index_size {
                let i = unsigned(&indices[k * index_size..], index_type) as usize;
                f(i, &values[k * size..(k + 1) * size]);
            }
        }
    }
}

/// The bytes of a buffer view, checked against its buffer's byteLength.
fn view_bytes<'d>(d: &'d GltfDocument, view: &::gltf::buffer::View) -> Result<&'d [u8], String> {
    let buffer = view.buffer();
    let declared = buffer.length();
    let end = view.offset().checked_add(view.length());
    match end {
        Some(end) if end <= declared => Ok(&d.buffers[buffer.index()][view.offset()..end]),
        _ => Err(format!(
            "buffer view {} (bytes {}..{}) lies outside buffer {} ({declared} bytes)",
            view.index(),
            view.offset(),
            view.offset() as u128 + view.length() as u128,
            buffer.index()
        )),
    }
}

/// `n` tightly packed elements of `size` bytes at `offset` in a view.
fn view_range<'d>(
    d: &'d GltfDocument,
    view: &::gltf::buffer::View,
    offset: usize,
    size: usize,
    n: usize,
) -> Result<&'d [u8], String> {
    let data = view_bytes(d, view)?;
    let end = size.checked_mul(n).and_then(|v| v.checked_add(offset));
    match end {
        Some(end) if end <= data.len() => Ok(&data[offset..end]),
        _ => Err(format!(
            "sparse data ({n} × {size} bytes from offset {offset}) runs past the end of buffer view {} ({} bytes)",
            view.index(),
            data.len()
        )),
    }
}

/// An unsigned integer component (little-endian).
fn unsigned(b: &[u8], ty: DataType) -> u32 {
    match ty {
        DataType::U8 => b[0] as u32,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// One component as f32: floats as stored, normalised integers mapped to [0, 1] (unsigned) or
/// [−1, 1] (signed, max(c/(2^(n−1) − 1), −1)) as the glTF specification defines.
fn component(b: &[u8], ty: DataType, normalized: bool) -> f32 {
    match (ty, normalized) {
        (DataType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (DataType::U8, true) => b[0] as f32 / 255.0,
        (DataType::U16, true) => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        (DataType::I8, true) => (b[0] as i8 as f32 / 127.0).max(-1.0),
        (DataType::I16, true) => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        (DataType::I8, false) => b[0] as i8 as f32,
        (DataType::I16, false) => i16::from_le_bytes([b[0], b[1]]) as f32,
        (ty, _) => unsigned(b, ty) as f32,
    }
}
