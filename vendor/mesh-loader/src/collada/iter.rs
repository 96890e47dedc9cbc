use std::{
    iter::{self, FusedIterator},
    ops::Range,
    slice,
};

use crate::{collada as ast, Face, Vec2, Vec3};

#[derive(Clone)]
pub(super) struct Mesh<'a> {
    pub(super) doc: &'a ast::Document<'a>,
    pub(super) xml: &'a ast::Geometry<'a>,
}

impl<'a> Mesh<'a> {
    pub(super) fn primitives(&self) -> Primitives<'a> {
        Primitives {
            mesh: self.clone(),
            iter: self.xml.mesh.primitives.iter().enumerate(),
        }
    }
}

pub(super) struct Primitives<'a> {
    mesh: Mesh<'a>,
    iter: iter::Enumerate<slice::Iter<'a, ast::Primitive<'a>>>,
}

impl<'a> Iterator for Primitives<'a> {
    type Item = Primitive<'a>;

    fn next(&mut self) -> Option<Self::Item> {
        self.iter.next().map(|(_index, xml)| Primitive {
            mesh: self.mesh.clone(),
            xml,
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.iter.size_hint()
    }
}

impl ExactSizeIterator for Primitives<'_> {}
impl FusedIterator for Primitives<'_> {}

#[derive(Clone)]
pub(super) struct Primitive<'a> {
    pub(super) mesh: Mesh<'a>,
    pub(super) xml: &'a ast::Primitive<'a>,
}

impl<'a> Primitive<'a> {
    pub(super) fn positions(&self) -> Positions<'a> {
        let input = match &self.xml.input {
            Some(input) => input,
            None => return Positions(None),
        };
        if self.mesh.xml.mesh.vertices.id == input.vertex.source {
            let position = &self.mesh.xml.mesh.vertices.input.position;
            let acc = match self.mesh.doc.get(&position.source) {
                Some(acc) => acc,
                None => return Positions(None),
            };
            let data = match self.mesh.doc.get(&acc.source).and_then(|d| d.as_float()) {
                Some(data) => data,
                None => return Positions(None),
            };
            // ["X", "Y", "Z"]
            if acc.stride < 3 || acc.params.len() < 3 || acc.params.iter().any(|p| p.ty != "float")
            {
                // TODO: error?
                return Positions(None);
            }
            if (acc.count as usize).saturating_mul(acc.stride as usize) > data.len() {
                return Positions(None);
            }
            Positions(Some((acc.count, data.chunks(acc.stride as usize))))
        } else {
            // TODO: search other mesh's vertices
            return Positions(None);
        }
    }

    pub(super) fn normals(&self) -> Normals<'a> {
        let acc = match &self.xml.input {
            Some(input) => match &input.normal {
                Some(normal) => match self.mesh.doc.get(&normal.source) {
                    Some(acc) => acc,
                    None => return Positions(None),
                },
                None => {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        match &self.mesh.xml.mesh.vertices.input.normal {
                            Some(normal) => match self.mesh.doc.get(&normal.source) {
                                Some(acc) => acc,
                                None => return Positions(None),
                            },
                            None => return Positions(None),
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return Positions(None);
                    }
                }
            },
            None => return Positions(None),
        };
        let data = match self.mesh.doc.get(&acc.source).and_then(|d| d.as_float()) {
            Some(data) => data,
            None => return Positions(None),
        };
        // ["X", "Y", "Z"]
        if acc.stride < 3 || acc.params.len() < 3 || acc.params.iter().any(|p| p.ty != "float") {
            // TODO: error?
            return Positions(None);
        }
        if (acc.count as usize).saturating_mul(acc.stride as usize) > data.len() {
            return Positions(None);
        }
        Positions(Some((acc.count, data.chunks(acc.stride as usize))))
    }

    pub(super) fn texcoords(&self, set: usize) -> Texcoords<'a> {
        let acc = match &self.xml.input {
            Some(input) => {
                if let Some(texcoord) = input.texcoord.get(set) {
                    match self.mesh.doc.get(&texcoord.source) {
                        Some(acc) => acc,
                        None => return Texcoords(None),
                    }
                } else if set == 0 {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        match &self.mesh.xml.mesh.vertices.input.texcoord {
                            Some(texcoord) => match self.mesh.doc.get(&texcoord.source) {
                                Some(acc) => acc,
                                None => return Texcoords(None),
                            },
                            None => return Texcoords(None),
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return Texcoords(None);
                    }
                } else {
                    return Texcoords(None);
                }
            }
            None => return Texcoords(None),
        };
        let data = match self.mesh.doc.get(&acc.source).and_then(|d| d.as_float()) {
            Some(data) => data,
            None => return Texcoords(None),
        };
        // ["S", "T"] or ["S", "T", "P"]
        if acc.stride < 2 || acc.params.len() < 2 || acc.params.iter().any(|p| p.ty != "float") {
            // TODO: error?
            return Texcoords(None);
        }
        if (acc.count as usize).saturating_mul(acc.stride as usize) > data.len() {
            return Texcoords(None);
        }
        let len = acc.count as usize * acc.stride as usize;
        Texcoords(Some(TexcoordsInner {
            iter: data[..len].chunks(acc.stride as usize),
        }))
    }

    pub(super) fn colors(&self) -> Colors<'a> {
        let acc = match &self.xml.input {
            Some(input) => match &input.color {
                Some(color) => match self.mesh.doc.get(&color.source) {
                    Some(acc) => acc,
                    None => return Positions(None),
                },
                None => {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        match &self.mesh.xml.mesh.vertices.input.color {
                            Some(color) => match self.mesh.doc.get(&color.source) {
                                Some(acc) => acc,
                                None => return Positions(None),
                            },
                            None => return Positions(None),
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return Positions(None);
                    }
                }
            },
            None => return Positions(None),
        };
        let data = match self.mesh.doc.get(&acc.source).and_then(|d| d.as_float()) {
            Some(data) => data,
            None => return Positions(None),
        };
        // ["R", "G", "B"] or ["R", "G", "B", "A"]
        if acc.stride < 3 || acc.params.len() < 3 || acc.params.iter().any(|p| p.ty != "float") {
            // TODO: error?
            return Positions(None);
        }
        if (acc.count as usize).saturating_mul(acc.stride as usize) > data.len() {
            return Positions(None);
        }
        Positions(Some((acc.count, data.chunks(acc.stride as usize))))
    }

    fn vertex_indices_inner(&self, offset: u32) -> IndicesInner<'a> {
        match self.xml.ty {
            ast::PrimitiveType::Lines | ast::PrimitiveType::LineStrips => IndicesInner::Skip,
            ast::PrimitiveType::Polylist | ast::PrimitiveType::Polygons => IndicesInner::Polylist {
                offset,
                indices: &self.xml.p,
                stride: self.xml.stride,
                index: 0,
                vcount: self.xml.vcount.iter(),
                range: None,
            },
            ast::PrimitiveType::Triangles => IndicesInner::Triangles {
                offset,
                indices: self.xml.p.chunks(self.xml.stride as usize),
            },
            ast::PrimitiveType::TriStrips | ast::PrimitiveType::TriFans => {
                IndicesInner::TriStrips {
                    offset,
                    indices: &self.xml.p,
                    stride: self.xml.stride,
                    index: 0,
                    vcount: self.xml.vcount.iter(),
                    range: None,
                }
            }
        }
    }

    fn vertex_indices_size(&self) -> u32 {
        match self.xml.ty {
            ast::PrimitiveType::Polylist | ast::PrimitiveType::Polygons => self
                .xml
                .vcount
                .iter()
                .fold(0u32, |n, count| n.saturating_add(count.saturating_sub(2))),
            ast::PrimitiveType::Triangles => self.xml.count,
            ast::PrimitiveType::TriStrips | ast::PrimitiveType::TriFans => self
                .xml
                .vcount
                .iter()
                .fold(0u32, |n, count| n.saturating_add(count.saturating_sub(2))),
            ast::PrimitiveType::Lines => 0,
            ast::PrimitiveType::LineStrips => 0,
        }
    }

    pub(super) fn vertex_indices(&self) -> VertexIndices<'a> {
        let offset = match &self.xml.input {
            Some(input) => input.vertex.offset,
            None => return VertexIndices::none(),
        };
        VertexIndices {
            remaining: self.vertex_indices_size(),
            inner: self.vertex_indices_inner(offset),
        }
    }

    pub(super) fn normal_indices(&self) -> VertexIndices<'a> {
        let offset = match &self.xml.input {
            Some(input) => match &input.normal {
                Some(normal) => normal.offset,
                None => {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        if self.mesh.xml.mesh.vertices.input.normal.is_some() {
                            input.vertex.offset
                        } else {
                            return VertexIndices::none();
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return VertexIndices::none();
                    }
                }
            },
            None => return VertexIndices::none(),
        };
        VertexIndices {
            remaining: self.vertex_indices_size(),
            inner: self.vertex_indices_inner(offset),
        }
    }

    pub(super) fn texcoord_indices(&self, set: usize) -> VertexIndices<'a> {
        let offset = match &self.xml.input {
            Some(input) => match input.texcoord.get(set) {
                Some(texcoord) => texcoord.offset,
                None => {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        if self.mesh.xml.mesh.vertices.input.texcoord.is_some() {
                            input.vertex.offset
                        } else {
                            return VertexIndices::none();
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return VertexIndices::none();
                    }
                }
            },
            None => return VertexIndices::none(),
        };
        VertexIndices {
            remaining: self.vertex_indices_size(),
            inner: self.vertex_indices_inner(offset),
        }
    }

    pub(super) fn color_indices(&self) -> VertexIndices<'a> {
        let offset = match &self.xml.input {
            Some(input) => match &input.color {
                Some(color) => color.offset,
                None => {
                    if self.mesh.xml.mesh.vertices.id == input.vertex.source {
                        if self.mesh.xml.mesh.vertices.input.color.is_some() {
                            input.vertex.offset
                        } else {
                            return VertexIndices::none();
                        }
                    } else {
                        // TODO: search other mesh's vertices
                        return VertexIndices::none();
                    }
                }
            },
            None => return VertexIndices::none(),
        };
        VertexIndices {
            remaining: self.vertex_indices_size(),
            inner: self.vertex_indices_inner(offset),
        }
    }
}

pub(super) struct Positions<'a>(Option<(u32, slice::Chunks<'a, f32>)>);

impl Iterator for Positions<'_> {
    type Item = Vec3;

    fn next(&mut self) -> Option<Self::Item> {
        let (count, iter) = self.0.as_mut()?;
        if *count == 0 {
            self.0 = None;
            return None;
        }
        let v = iter.next()?;
        *count -= 1;
        if *count == 0 {
            self.0 = None;
        }
        Some([v[0], v[1], v[2]])
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        match &self.0 {
            Some((_, iter)) => iter.size_hint(),
            None => (0, Some(0)),
        }
    }
}

impl ExactSizeIterator for Positions<'_> {}
impl FusedIterator for Positions<'_> {}

pub(super) type Normals<'a> = Positions<'a>;
pub(super) type Colors<'a> = Positions<'a>;

pub(super) struct Texcoords<'a>(Option<TexcoordsInner<'a>>);

struct TexcoordsInner<'a> {
    iter: slice::Chunks<'a, f32>,
}

impl Iterator for Texcoords<'_> {
    type Item = Vec2;

    fn next(&mut self) -> Option<Self::Item> {
        let inner = self.0.as_mut()?;
        match inner.iter.next() {
            Some(v) => Some([v[0], v[1]]),
            None => {
                self.0 = None;
                None
            }
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        match &self.0 {
            Some(inner) => inner.iter.size_hint(),
            None => (0, Some(0)),
        }
    }
}

impl ExactSizeIterator for Texcoords<'_> {}
impl FusedIterator for Texcoords<'_> {}

pub(super) struct VertexIndices<'a> {
    remaining: u32,
    inner: IndicesInner<'a>,
}

enum IndicesInner<'a> {
    Polylist {
        offset: u32,
        indices: &'a [u32],
        stride: u32,
        vcount: slice::Iter<'a, u32>,
        index: usize,
        range: Option<Range<u32>>,
    },
    Triangles {
        offset: u32,
        indices: slice::Chunks<'a, u32>,
    },
    TriStrips {
        offset: u32,
        indices: &'a [u32],
        stride: u32,
        vcount: slice::Iter<'a, u32>,
        index: usize,
        range: Option<Range<u32>>,
    },
    Skip,
    None,
}

impl VertexIndices<'_> {
    const fn none() -> Self {
        Self {
            remaining: 0,
            inner: IndicesInner::None,
        }
    }
}

impl Iterator for VertexIndices<'_> {
    type Item = Face;

    // gymfleet patch: a loop instead of recursion for skipped polygons (a document with
    // many of them overflowed the stack), checked index reads (`None` ends the faces
    // when the document's indices run out), and a polygon of fewer than three vertices
    // (skipped, as before) now moves past its own indices.
    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if self.remaining == 0 {
                return None;
            }
            self.remaining -= 1;

            match &mut self.inner {
                IndicesInner::Polylist {
                    offset,
                    indices,
                    stride,
                    index,
                    vcount,
                    range,
                }
                | IndicesInner::TriStrips {
                    offset,
                    indices,
                    stride,
                    index,
                    vcount,
                    range,
                } => {
                    let offset = *offset as usize;
                    let stride = *stride as usize;
                    if let Some(r) = range {
                        if let Some(k) = r.next() {
                            let x = *index + offset;
                            let y = *index + offset + stride * k as usize;
                            let z = *index + offset + stride * (k as usize + 1);
                            let value = [*indices.get(x)?, *indices.get(y)?, *indices.get(z)?];
                            // NOTE: Do *not* increment index until range ends.
                            return Some(value);
                        }
                        let vc = r.end + 1;
                        *index += stride * vc as usize;
                        *range = None;
                    }
                    let vc = *vcount.next()?;
                    match vc {
                        3 => {
                            let x = *index + offset;
                            let y = *index + offset + stride;
                            let z = *index + offset + stride * 2;
                            let value = [*indices.get(x)?, *indices.get(y)?, *indices.get(z)?];
                            *index += stride * vc as usize;
                            return Some(value);
                        }
                        0..=2 => {
                            *index += stride * vc as usize;
                        }
                        _ => {
                            let mut ri = 1..vc - 1;
                            let k = ri.next()?;
                            let x = *index + offset;
                            let y = *index + offset + stride * k as usize;
                            let z = *index + offset + stride * (k as usize + 1);
                            let value = [*indices.get(x)?, *indices.get(y)?, *indices.get(z)?];
                            // Set range for next call.
                            // NOTE: Do *not* increment index until range ends.
                            *range = Some(ri);
                            return Some(value);
                        }
                    }
                }
                IndicesInner::Triangles { offset, indices } => {
                    let offset = *offset as usize;
                    let indices1 = indices.next()?;
                    let indices2 = indices.next()?;
                    let indices3 = indices.next()?;
                    return Some([
                        *indices1.get(offset)?,
                        *indices2.get(offset)?,
                        *indices3.get(offset)?,
                    ]);
                }
                IndicesInner::Skip => {}
                IndicesInner::None => return None,
            }
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.remaining as usize, Some(self.remaining as usize))
    }
}

impl ExactSizeIterator for VertexIndices<'_> {}
impl FusedIterator for VertexIndices<'_> {}
