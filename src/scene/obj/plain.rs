//! A parallel parser for *plain* OBJ files: the scanned meshes (the Stanford dragon, bunny,
//! armadillo) that hold nothing but positions and faces.
//!
//! tobj reads one line at a time into a new `String` and matches vertices through a hash map; for
//! a large scanned mesh that is most of the scene load (docs/performance-log.md). A plain file
//! needs neither: this parser splits the bytes into blocks of whole lines, parses the blocks on
//! all cores, and renumbers the vertices in order of first use exactly as tobj's per-attribute
//! mode does.
//!
//! It accepts a file only when it can give tobj's answer bit for bit: the file is ASCII, its
//! lines are `v x y z`, faces of at least three plain positive indices (fan-triangulated as tobj
//! does), `mtllib` (handed back to tobj), or lines tobj ignores (comments, `s`, unknown keywords).
//! Anything else (texture coordinates, normals, groups, `usemtl`, relative or out-of-range
//! indices, a `w` or colour after a position, a number tobj would refuse) returns `None`, and the
//! caller gives the whole file to tobj, which then also reports any error in its own words.

use rayon::prelude::*;

/// What a plain file holds, as tobj would return it.
pub struct PlainObj<'a> {
    /// The file's one model: its referenced positions in order of first use and its triangles,
    /// named as tobj names a model without an `o` or `g` line.
    pub model: tobj::Model,
    /// The file's `mtllib` lines in order, for tobj to load the materials from.
    pub material_lines: Vec<&'a str>,
}

/// The name tobj gives the model of a file without `o` or `g` lines.
const TOBJ_DEFAULT_NAME: &str = "unnamed_object";

/// Blocks are at least this long, so that small files stay on one thread.
const MIN_BLOCK_BYTES: usize = 1 << 16;

/// Parses `bytes` when it is a plain OBJ file (see the module documentation), else `None`.
pub fn parse(bytes: &[u8]) -> Option<PlainObj<'_>> {
    // ASCII only: then splitting at ASCII whitespace is exactly tobj's `split_whitespace`.
    if !bytes.is_ascii() {
        return None;
    }
    let text = std::str::from_utf8(bytes).ok()?;
    let blocks: Vec<Block> = line_blocks(text)
        .into_par_iter()
        .map(parse_block)
        .collect::<Option<_>>()?;

    let vertex_count: usize = blocks.iter().map(|b| b.positions.len()).sum();
    if vertex_count >= u32::MAX as usize {
        return None;
    }
    let all_positions: Vec<[f64; 3]> = blocks.iter().flat_map(|b| b.positions.iter().copied()).collect();
    // Renumber in order of first use, as tobj's per-attribute export does; vertices no face
    // uses are dropped there too.
    const UNSEEN: u32 = u32::MAX;
    let mut new_index = vec![UNSEEN; vertex_count];
    let triangle_count: usize = blocks.iter().map(|b| b.triangles.len()).sum();
    let mut indices = Vec::with_capacity(3 * triangle_count);
    let mut positions = Vec::with_capacity(3 * vertex_count);
    for &i in blocks.iter().flat_map(|b| b.triangles.iter()).flatten() {
        let slot = new_index.get_mut(i as usize)?; // out of range: tobj's error
        if *slot == UNSEEN {
            *slot = (positions.len() / 3) as u32;
            positions.extend_from_slice(&all_positions[i as usize]);
        }
        indices.push(*slot);
    }
    if indices.is_empty() {
        return None;
    }
    Some(PlainObj {
        model: tobj::Model::new(
            tobj::Mesh {
                positions,
                indices,
                ..Default::default()
            },
            TOBJ_DEFAULT_NAME.to_owned(),
        ),
        material_lines: blocks.into_iter().flat_map(|b| b.material_lines).collect(),
    })
}

/// What one block of lines holds: positions, triangles with 0-based file-wide vertex indices.
struct Block<'a> {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    material_lines: Vec<&'a str>,
}

/// Cuts `text` into blocks of whole lines, about two per thread and at least
/// [`MIN_BLOCK_BYTES`] long. The result of [`parse`] does not depend on the cut.
fn line_blocks(text: &str) -> Vec<&str> {
    let wanted = (text.len() / MIN_BLOCK_BYTES).clamp(1, 2 * rayon::current_num_threads());
    let size = text.len().div_ceil(wanted);
    let mut blocks = Vec::with_capacity(wanted);
    let mut rest = text;
    while !rest.is_empty() {
        let end = match memchr::memchr(b'\n', &rest.as_bytes()[size.min(rest.len() - 1)..]) {
            Some(i) => size.min(rest.len() - 1) + i + 1,
            None => rest.len(),
        };
        let (block, tail) = rest.split_at(end);
        blocks.push(block);
        rest = tail;
    }
    blocks
}

/// The whitespace-separated words of one line (without its `\n`), split where tobj's
/// `split_whitespace` splits an ASCII line: at the ASCII characters `char::is_whitespace` accepts,
/// which unlike `u8::is_ascii_whitespace` include the vertical tab.
struct Words<'a> {
    line: &'a str,
    at: usize,
}

impl<'a> Words<'a> {
    fn new(line: &'a str) -> Self {
        Words { line, at: 0 }
    }
}

/// Whether `b` separates words: space, tab, vertical tab, form feed or carriage return.
fn is_space(b: u8) -> bool {
    const SPACES: u64 = 1 << b' ' | 1 << b'\t' | 1 << 0x0b | 1 << 0x0c | 1 << b'\r';
    b <= b' ' && SPACES >> b & 1 == 1
}

impl<'a> Iterator for Words<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        let bytes = self.line.as_bytes();
        let mut end = self.at;
        while end < bytes.len() && is_space(bytes[end]) {
            end += 1;
        }
        let start = end;
        while end < bytes.len() && !is_space(bytes[end]) {
            end += 1;
        }
        self.at = end;
        (start < end).then(|| &self.line[start..end])
    }
}

/// Parses one block of lines, or `None` if a line is not plain.
fn parse_block(block: &str) -> Option<Block<'_>> {
    let mut out = Block {
        positions: Vec::with_capacity(block.len() / 64),
        triangles: Vec::with_capacity(block.len() / 32),
        material_lines: Vec::new(),
    };
    let mut rest = block;
    while !rest.is_empty() {
        let end = memchr::memchr(b'\n', rest.as_bytes()).unwrap_or(rest.len());
        let line = &rest[..end];
        rest = rest.get(end + 1..).unwrap_or("");
        let mut words = Words::new(line);
        match words.next() {
            Some("v") => {
                let mut p = [0.0f64; 3];
                for c in &mut p {
                    *c = words.next()?.parse().ok()?;
                }
                if words.next().is_some() {
                    return None; // a w or a colour: tobj's handling
                }
                out.positions.push(p);
            }
            Some("f") => {
                let first = vertex_index(words.next()?)?;
                let mut previous = vertex_index(words.next()?)?;
                let mut any = false;
                for word in words {
                    let next = vertex_index(word)?;
                    out.triangles.push([first, previous, next]);
                    previous = next;
                    any = true;
                }
                if !any {
                    return None; // a point or a line: tobj's handling
                }
            }
            // tobj keeps `line` whole here (file names may hold spaces) and trims the `\r` of a
            // CRLF line itself when it reads these lines back.
            Some("mtllib") => out.material_lines.push(line),
            Some("vt" | "vn" | "l" | "o" | "g" | "usemtl") => return None,
            _ => {} // comments, blank lines, `s` and other keywords tobj ignores
        }
    }
    Some(out)
}

/// A face word made only of decimal digits, as a 0-based index; `None` for anything else (a
/// `/`, a sign, 0, a value past u32).
fn vertex_index(word: &str) -> Option<u32> {
    let mut one_based = 0u32;
    for b in word.bytes() {
        let digit = b.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        one_based = one_based.checked_mul(10)?.checked_add(u32::from(digit))?;
    }
    one_based.checked_sub(1)
}

#[cfg(test)]
#[path = "plain_tests.rs"]
mod tests;
