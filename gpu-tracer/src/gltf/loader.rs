//! Reading a glTF file ([`Loader`]): the file, its document as validated by
//! the `gltf` crate, and its buffers. The `gltf` crate indexes some arrays
//! without bounds checks and its readers panic on some malformed data, so
//! this is also where the file is checked first: the GLB header, the raw
//! JSON, buffer views, URIs and every accessor before it is read. Errors
//! name the element at fault ([`label`], [`content_error`]).

use crate::error::{Error, Result};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Checked;
use std::path::Path;

/// The extension that allows integer positions and more integer texture
/// coordinates (files that use it must list it in `extensionsUsed`; read
/// by the `attribute` module).
pub(super) const MESH_QUANTIZATION: &str = "KHR_mesh_quantization";

/// Extensions implemented here rather than by the `gltf` crate (whose
/// validation refuses files that require an extension it does not know).
const LOADER_EXTENSIONS: &[&str] = &[MESH_QUANTIZATION];

/// Largest element count of a sparse accessor without a base buffer view
/// (its elements are materialised: 2^24 positions are 192 MiB).
const MAX_SPARSE_ONLY_COUNT: usize = 1 << 24;

/// `kind 'name'` or `kind index`.
pub(super) fn label(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("{kind} '{n}'"),
        None => format!("{kind} {index}"),
    }
}

/// The loading state: the validated document and its buffers.
pub(super) struct Loader<'p> {
    pub(super) path: &'p Path,
    /// Directory that relative URIs are resolved against.
    pub(super) base: &'p Path,
    pub(super) document: gltf::Document,
    pub(super) buffers: Vec<gltf::buffer::Data>,
    pub(super) notices: Vec<String>,
}

impl<'p> Loader<'p> {
    pub(super) fn content(&self, element: impl Into<String>, reason: impl Into<String>) -> Error {
        content_error(self.path, element, reason)
    }

    /// Reads, parses and validates the file and imports its buffers.
    pub(super) fn open(path: &'p Path) -> Result<Self> {
        let load = |element: &str, source| Error::GltfLoad {
            path: path.to_path_buf(),
            element: element.to_string(),
            source,
        };
        let bytes = std::fs::read(path).map_err(|e| load("file", gltf::Error::Io(e)))?;
        check_glb_header(path, &bytes)?;
        let gltf::Gltf { document, mut blob } =
            gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| load("file", e))?;
        drop(bytes);
        // The gltf crate indexes some arrays without bounds checks (in its
        // validation and accessors): check those first.
        precheck_json(path, document.as_json())?;
        let mut json = document.into_json();
        // Extensions this loader implements but the `gltf` crate's validation
        // does not know: accepted when required.
        json.extensions_required
            .retain(|e| !LOADER_EXTENSIONS.contains(&e.as_str()));
        let document = gltf::Document::from_json(json).map_err(|e| load("JSON validation", e))?;
        check_buffer_views(path, &document)?;
        let base = path.parent().unwrap_or(Path::new("."));

        let mut buffers = Vec::new();
        for buffer in document.buffers() {
            let element = match buffer.source() {
                gltf::buffer::Source::Uri(uri) => {
                    check_uri(path, &format!("buffer {}", buffer.index()), uri)?;
                    format!("buffer {} ('{}')", buffer.index(), short_uri(uri))
                }
                gltf::buffer::Source::Bin => format!("buffer {} (GLB BIN chunk)", buffer.index()),
            };
            let data = gltf::buffer::Data::from_source_and_blob(buffer.source(), Some(base), &mut blob)
                .map_err(|e| load(&element, e))?;
            if data.0.len() < buffer.length() {
                return Err(load(
                    &element,
                    gltf::Error::BufferLength {
                        buffer: buffer.index(),
                        expected: buffer.length(),
                        actual: data.0.len(),
                    },
                ));
            }
            buffers.push(data);
        }
        Ok(Loader {
            path,
            base,
            document,
            buffers,
            notices: Vec::new(),
        })
    }

    /// Checks an accessor before the `gltf` readers touch it (they panic on
    /// unexpected types and overflowing ranges): type in `allowed` (integer
    /// types normalised when `normalized_ints`), at least one element, and
    /// every element (base, sparse indices and values) inside its buffer
    /// view, which is inside its buffer. Sparse indices must be strictly
    /// increasing and in range.
    pub(super) fn check_accessor(
        &self,
        acc: &gltf::Accessor,
        element: &str,
        what: &str,
        allowed: &[(DataType, Dimensions)],
        normalized_ints: bool,
    ) -> Result<()> {
        let fail = |reason: String| {
            Err(self.content(element, format!("{what} (accessor {}): {reason}", acc.index())))
        };
        let ty = (acc.data_type(), acc.dimensions());
        if !allowed.contains(&ty) {
            let expected: Vec<String> = allowed.iter().map(|(t, d)| format!("{d:?} of {t:?}")).collect();
            return fail(format!(
                "is {:?} of {:?}, expected {}",
                ty.1,
                ty.0,
                expected.join(" or ")
            ));
        }
        if normalized_ints && acc.data_type() != DataType::F32 && !acc.normalized() {
            return fail("integer values must be normalized".into());
        }
        let count = acc.count();
        if count == 0 {
            return fail("has no element".into());
        }
        if acc.view().is_none() && count > MAX_SPARSE_ONLY_COUNT {
            // Sparse without a base view: nothing bounds `count` by the file size.
            return fail(format!(
                "{count} elements without a buffer view (at most {MAX_SPARSE_ONLY_COUNT} are accepted)"
            ));
        }
        let size = acc.size();
        if let Some(view) = acc.view() {
            if let Err(reason) =
                self.check_range(&view, acc.offset(), view.stride().unwrap_or(size), size, count)
            {
                return fail(reason);
            }
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            if n == 0 || n > count {
                return fail(format!("sparse count {n} is not in 1..={count}"));
            }
            let indices = sparse.indices();
            let iview = indices.view();
            let isize = indices.index_type().size();
            let istride = iview.stride().unwrap_or(isize);
            if let Err(reason) = self.check_range(&iview, indices.offset(), istride, isize, n) {
                return fail(format!("sparse indices: {reason}"));
            }
            let vview = sparse.values().view();
            if let Err(reason) = self.check_range(
                &vview,
                sparse.values().offset(),
                vview.stride().unwrap_or(size),
                size,
                n,
            ) {
                return fail(format!("sparse values: {reason}"));
            }
            let data = self
                .buffers
                .get(iview.buffer().index())
                .map_or(&[][..], |d| d.0.as_slice());
            let mut previous: Option<u32> = None;
            for k in 0..n {
                // In range: checked by `check_range` above.
                let at = iview.offset() + indices.offset() + k * istride;
                let index = match data.get(at..at + isize) {
                    Some(&[b]) => u32::from(b),
                    Some(&[b0, b1]) => u32::from(u16::from_le_bytes([b0, b1])),
                    Some(&[b0, b1, b2, b3]) => u32::from_le_bytes([b0, b1, b2, b3]),
                    _ => return fail(format!("sparse index {k} cannot be read")),
                };
                if index as usize >= count || previous.is_some_and(|p| index <= p) {
                    return fail(format!(
                        "sparse index {k} is {index}: indices must be strictly increasing and below {count}"
                    ));
                }
                previous = Some(index);
            }
        }
        Ok(())
    }

    /// `count` elements of `size` bytes every `stride` bytes from `offset`
    /// lie inside `view`, and `view` inside its buffer's data.
    fn check_range(
        &self,
        view: &gltf::buffer::View,
        offset: usize,
        stride: usize,
        size: usize,
        count: usize,
    ) -> std::result::Result<(), String> {
        if stride < size {
            return Err(format!(
                "byte stride {stride} is smaller than the element size {size}"
            ));
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|x| x.checked_add(offset))
            .and_then(|x| x.checked_add(size));
        if end.is_none_or(|end| end > view.length()) {
            return Err(format!(
                "{count} elements of {size} bytes (stride {stride}) from byte {offset} do not fit buffer view {} of {} bytes",
                view.index(),
                view.length()
            ));
        }
        let buffer_len = self.buffers.get(view.buffer().index()).map_or(0, |d| d.0.len());
        if view
            .offset()
            .checked_add(view.length())
            .is_none_or(|e| e > buffer_len)
        {
            return Err(format!("buffer view {} lies outside its buffer", view.index()));
        }
        Ok(())
    }
}

pub(super) fn content_error(path: &Path, element: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::GltfContent {
        path: path.to_path_buf(),
        element: element.into(),
        reason: reason.into(),
    }
}

/// The GLB header's declared length must be at least the header's and at
/// most the file's (the `gltf` crate would underflow or report a generic
/// error).
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<()> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    match word(8) {
        None => Err(content_error(
            path,
            "GLB header",
            "the file is shorter than the 12-byte header",
        )),
        Some(length) if length < 12 => Err(content_error(
            path,
            "GLB header",
            format!("declared length {length} is shorter than the header"),
        )),
        Some(length) if length > bytes.len() => Err(content_error(
            path,
            "GLB header",
            format!(
                "declares {length} bytes but the file has {} (truncated?)",
                bytes.len()
            ),
        )),
        Some(_) => Ok(()),
    }
}

/// Checks, on the raw JSON, what the `gltf` crate indexes without bounds
/// checks during validation or import.
fn precheck_json(path: &Path, root: &gltf::json::Root) -> Result<()> {
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &primitive.attributes {
                if index.value() >= accessors {
                    let name = match semantic {
                        Checked::Valid(s) => s.to_string(),
                        Checked::Invalid => "attribute".into(),
                    };
                    return Err(content_error(
                        path,
                        format!("{} primitive {p}", label("mesh", m, mesh.name.as_deref())),
                        format!(
                            "{name} names accessor {}, but the file has {accessors} accessors",
                            index.value()
                        ),
                    ));
                }
            }
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) => camera.perspective.is_none(),
            Checked::Valid(Type::Orthographic) => camera.orthographic.is_none(),
            Checked::Invalid => false, // reported by validation
        };
        if missing {
            return Err(content_error(
                path,
                label("camera", i, camera.name.as_deref()),
                "has no parameters for its type",
            ));
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        let element = || label("image", i, image.name.as_deref());
        match (&image.buffer_view, &image.uri) {
            (Some(_), _) if image.mime_type.is_none() => {
                return Err(content_error(
                    path,
                    element(),
                    "is in a buffer view but has no mimeType",
                ))
            }
            (None, None) => return Err(content_error(path, element(), "has neither uri nor bufferView")),
            _ => {}
        }
    }
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let element = || format!("{} channel {c}", label("animation", a, animation.name.as_deref()));
            if channel.target.node.value() >= root.nodes.len() {
                return Err(content_error(
                    path,
                    element(),
                    format!(
                        "targets node {}, but the file has {} nodes",
                        channel.target.node.value(),
                        root.nodes.len()
                    ),
                ));
            }
            if matches!(channel.target.path, Checked::Invalid) {
                return Err(content_error(path, element(), "unknown target path"));
            }
        }
    }
    Ok(())
}

/// Every buffer view lies inside its buffer's declared length.
fn check_buffer_views(path: &Path, document: &gltf::Document) -> Result<()> {
    for view in document.views() {
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|e| e > view.buffer().length()) {
            return Err(content_error(
                path,
                format!("buffer view {}", view.index()),
                format!(
                    "bytes {}..+{} exceed buffer {} of {} bytes",
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    view.buffer().length()
                ),
            ));
        }
    }
    Ok(())
}

/// A relative URI must percent-decode to UTF-8 (the `gltf` crate panics
/// otherwise).
pub(super) fn check_uri(path: &Path, element: &str, uri: &str) -> Result<()> {
    if uri.contains(':') {
        return Ok(()); // data: / file: / unsupported schemes are handled by gltf
    }
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (bytes[i], bytes.get(i + 1).copied(), bytes.get(i + 2).copied()) {
            (b'%', Some(h), Some(l)) if hex(h).is_some() && hex(l).is_some() => {
                decoded.push((hex(h).unwrap_or(0) * 16 + hex(l).unwrap_or(0)) as u8);
                i += 3;
            }
            (b, _, _) => {
                decoded.push(b);
                i += 1;
            }
        }
    }
    if std::str::from_utf8(&decoded).is_err() {
        return Err(content_error(
            path,
            element,
            format!("URI '{uri}' does not percent-decode to UTF-8"),
        ));
    }
    Ok(())
}

/// A URI for messages: data URIs shortened.
pub(super) fn short_uri(uri: &str) -> String {
    if uri.starts_with("data:") {
        let head: String = uri.chars().take(32).collect();
        format!("{head}...")
    } else {
        uri.to_string()
    }
}

#[cfg(test)]
mod tests {
    use crate::error::Error;
    use crate::gltf::load_gltf;
    use crate::gltf::tests::{
        content_error, fixture, fixture_copy, load, load_patched, quad_accessor, read_json, write_json,
    };
    use serde_json::{json, Value};
    use std::fs;

    /// A `.glb` container of `doc` and `bin`.
    fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
        let mut json_chunk = serde_json::to_vec(doc).expect("JSON");
        while json_chunk.len() & 3 != 0 {
            json_chunk.push(b' ');
        }
        let mut bin = bin.to_vec();
        while bin.len() & 3 != 0 {
            bin.push(0);
        }
        let total = 28 + json_chunk.len() + bin.len();
        let mut out = b"glTF".to_vec();
        for word in [2, total as u32, json_chunk.len() as u32] {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_chunk);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    fn base64(bytes: &[u8]) -> String {
        const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
            let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
            for k in 0..4 {
                if k <= chunk.len() {
                    out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    /// The textured quad as a `.glb` (image in the BIN chunk) and as a
    /// `.gltf` with data URIs load to the same scene as the `.gltf` + `.bin`.
    #[test]
    fn glb_gltf_bin_and_data_uris_give_the_same_scene() {
        let reference = load(&fixture("textured_quad.gltf"));
        let dir = tempfile::tempdir().expect("temp dir");
        let doc = read_json(&fixture("textured_quad.gltf"));
        let bin = fs::read(fixture("textured_quad.bin")).expect("bin");
        let png = fs::read(fixture("checker.png")).expect("png");

        let mut packed = doc.clone();
        let mut data = bin.clone();
        let png_offset = data.len().next_multiple_of(4);
        data.resize(png_offset, 0);
        data.extend_from_slice(&png);
        let views = packed["bufferViews"].as_array_mut().expect("views");
        views.push(json!({"buffer": 0, "byteOffset": png_offset, "byteLength": png.len()}));
        let png_view = views.len() - 1;
        packed["images"] = json!([{"bufferView": png_view, "mimeType": "image/png", "name": "checker"}]);
        packed["buffers"] = json!([{"byteLength": data.len()}]);
        let glb_path = dir.path().join("quad.glb");
        fs::write(&glb_path, glb(&packed, &data)).expect("write");
        assert_eq!(load(&glb_path), reference);

        let mut embedded = doc;
        embedded["buffers"][0]["uri"] =
            json!(format!("data:application/octet-stream;base64,{}", base64(&bin)));
        embedded["images"][0]["uri"] = json!(format!("data:image/png;base64,{}", base64(&png)));
        let path = dir.path().join("embedded.gltf");
        write_json(&path, &embedded);
        assert_eq!(load(&path), reference);
    }

    #[test]
    fn missing_file_truncated_glb_and_missing_bin_are_errors() {
        let dir = fixture_copy();
        let err = load_gltf(dir.path().join("nope.gltf"), None).expect_err("missing");
        assert!(
            matches!(&err, Error::GltfLoad { source: gltf::Error::Io(_), element, .. } if element == "file"),
            "{err}"
        );
        assert!(err.to_string().contains("nope.gltf"), "{err}");
        assert!(std::error::Error::source(&err).is_some());

        // Every truncation of a .glb is an error, never a panic.
        let bytes = fs::read(fixture("hierarchy.glb")).expect("glb");
        let path = dir.path().join("cut.glb");
        for len in 0..bytes.len() {
            fs::write(&path, &bytes[..len]).expect("write");
            assert!(load_gltf(&path, None).is_err(), "truncated to {len} bytes");
        }
        fs::write(&path, &bytes[..bytes.len() / 2]).expect("write");
        let (element, reason) = content_error(load_gltf(&path, None));
        assert!(
            element == "GLB header" && reason.contains("truncated"),
            "{reason}"
        );

        fs::remove_file(dir.path().join("textured_quad.bin")).expect("rm");
        let err = load_gltf(dir.path().join("textured_quad.gltf"), None).expect_err("no bin");
        match &err {
            Error::GltfLoad {
                element,
                source: gltf::Error::Io(_),
                ..
            } => assert!(element.contains("textured_quad.bin"), "{element}"),
            other => panic!("{other:?}"),
        }
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        // A .bin shorter than declared.
        fs::write(dir.path().join("textured_quad.bin"), [0u8; 8]).expect("write");
        let err = load_gltf(dir.path().join("textured_quad.gltf"), None).expect_err("short bin");
        assert!(
            matches!(
                err,
                Error::GltfLoad {
                    source: gltf::Error::BufferLength { .. },
                    ..
                }
            ),
            "{err}"
        );
    }

    #[test]
    fn bad_accessor_indices_are_errors() {
        let (element, reason) = content_error(load_patched(|doc, _| {
            doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99);
        }));
        assert!(element.contains("mesh 'checker_quad' primitive 0"), "{element}");
        assert!(reason.contains("accessor 99"), "{reason}");
        let err =
            load_patched(|doc, _| doc["meshes"][0]["primitives"][0]["indices"] = json!(99)).expect_err("bad");
        assert!(
            matches!(
                &err,
                Error::GltfLoad {
                    source: gltf::Error::Validation(_),
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        // An accessor of the wrong type (the gltf readers would panic on it).
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "POSITION");
            doc["accessors"][a]["type"] = json!("VEC4");
        }));
        assert!(reason.contains("POSITION") && reason.contains("Vec4"), "{reason}");
        // An accessor running past its buffer view.
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a]["count"] = json!(1000);
        }));
        assert!(reason.contains("do not fit"), "{reason}");
        // A buffer view past its buffer.
        let (element, _) = content_error(load_patched(|doc, _| {
            doc["bufferViews"][0]["byteLength"] = json!(4000)
        }));
        assert_eq!(element, "buffer view 0");
        // An animation channel naming a node that does not exist.
        let (element, _) = content_error(load_patched(|doc, _| {
            doc["animations"] = json!([{
                "samplers": [{"input": 0, "output": 0}],
                "channels": [{"sampler": 0, "target": {"node": 42, "path": "translation"}}]
            }]);
        }));
        assert_eq!(element, "animation 0 channel 0");
    }
}
