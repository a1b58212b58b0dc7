//! A small builder for synthetic GLB files: binary data appended as buffer views, the JSON
//! written by each test. Test infrastructure only; it shares nothing with the loader.

/// The binary chunk and the buffer views over it, as JSON.
#[derive(Default)]
pub struct Bin {
    pub bytes: Vec<u8>,
    views: Vec<String>,
}

impl Bin {
    /// Appends `bytes` (4-byte aligned) as a new buffer view; returns its index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bytes.len(),
            bytes.len()
        ));
        self.bytes.extend_from_slice(bytes);
        self.views.len() - 1
    }

    pub fn f32s(&mut self, values: &[f32]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.view(&bytes)
    }

    /// `"buffers"` and `"bufferViews"` members for the JSON.
    pub fn json(&self) -> String {
        let mut len = self.bytes.len();
        while !len.is_multiple_of(4) {
            len += 1;
        }
        format!(
            r#""buffers":[{{"byteLength":{len}}}],"bufferViews":[{}]"#,
            self.views.join(",")
        )
    }

    /// A GLB of `json` (which must include [`Bin::json`]) and this binary chunk.
    pub fn glb(&self, json: &str) -> Vec<u8> {
        glb(json, &self.bytes)
    }
}

/// A GLB holding `json` and the binary chunk `bin` (both padded to 4 bytes).
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let json = pad(json.as_bytes().to_vec(), b' ');
    let bin = pad(bin.to_vec(), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// The triangle (0,0,0), (1,0,0), (0,1,0) as view 0 (positions) and accessor 0.
pub fn triangle(bin: &mut Bin) -> &'static str {
    bin.f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    r#"{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}"#
}

/// A 1×1 PNG, for materials that need a texture.
pub fn png() -> Vec<u8> {
    let mut bytes = Vec::new();
    image::DynamicImage::ImageRgba8(image::RgbaImage::from_pixel(1, 1, image::Rgba([255; 4])))
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .expect("encode png");
    bytes
}

/// The binary chunk of the GLB at `path`, read from its chunk headers.
pub fn glb_bin(path: &std::path::Path) -> Vec<u8> {
    let bytes = std::fs::read(path).expect("read glb");
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let json_len = u32_at(12) as usize;
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bin_at) as usize;
    assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
    bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec()
}

/// `count` little-endian f32 values at byte `offset` of `bin`.
pub fn f32s_at(bin: &[u8], offset: usize, count: usize) -> Vec<f32> {
    bin[offset..offset + 4 * count]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect()
}
