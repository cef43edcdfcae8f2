//! glTF buffer files are read only from inside the glTF's folder, only when they are regular
//! files, and never past their declared `byteLength` (docs/gltf.md, "Buffers"): what cannot be
//! committed to the bad-input corpus (a FIFO, symbolic links, a 6 GB sparse file, `/dev/zero`)
//! is built here in a temporary folder. Every refusal names `buffers[0].uri` and the glTF file,
//! and no message repeats the bytes of a file outside the folder.

use shadowtruth::scene::{Problem, load_scene, load_scene_str};
use std::path::PathBuf;

/// What the file outside the glTF's folder holds; no message may repeat it.
const SECRET: &[u8] = b"SECRET-BYTES-OF-A-FILE-OUTSIDE-THE-FOLDER-0123456789";

/// A triangle's positions (f32 VEC3), 36 bytes.
fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0].iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A glTF whose one triangle is read from buffer 0 at `uri`, declared `byte_length` bytes long.
fn gltf_text(uri: &str, byte_length: u64) -> String {
    serde_json::json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "uri": uri, "byteLength": byte_length }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, -1], "max": [1, 0, 0] }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "nodes": [{ "mesh": 0, "name": "triangle" }],
        "scenes": [{ "nodes": [0] }],
        "scene": 0
    })
    .to_string()
}

/// A folder `scene/` holding the glTFs, beside `outside.bin` (the secret, then a triangle).
struct Folders {
    root: tempfile::TempDir,
}

impl Folders {
    fn new() -> Self {
        let root = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(root.path().join("scene/sub")).unwrap();
        std::fs::write(root.path().join("outside.bin"), [SECRET, &triangle_bytes()].concat()).unwrap();
        Folders { root }
    }

    fn scene(&self) -> PathBuf {
        self.root.path().join("scene")
    }

    fn outside(&self) -> PathBuf {
        self.root.path().join("outside.bin")
    }

    /// Writes `scene/model.gltf` reading buffer 0 from `uri` and loads it.
    fn load(&self, uri: &str, byte_length: u64) -> Result<shadowtruth::scene::Scene, Vec<Problem>> {
        let path = self.scene().join("model.gltf");
        std::fs::write(&path, gltf_text(uri, byte_length)).unwrap();
        load_scene(&path).map_err(|e| e.problems)
    }

    /// The one problem of loading `uri`: at `field` of `scene/model.gltf`; returns its message.
    fn refused(&self, uri: &str, byte_length: u64, field: &str) -> String {
        let problems = self.load(uri, byte_length).expect_err(uri);
        assert_eq!(problems.len(), 1, "{uri}: {problems:?}");
        let problem = &problems[0];
        assert_eq!(problem.file, self.scene().join("model.gltf"), "{uri}");
        assert_eq!(problem.path, field, "{uri}: {}", problem.message);
        let secret = String::from_utf8_lossy(&SECRET[..6]).into_owned();
        assert!(!problem.message.contains(&secret), "{uri}: the message repeats bytes: {}", problem.message);
        problem.message.clone()
    }
}

#[test]
fn buffer_files_inside_the_folder_load_up_to_their_byte_length() {
    let folders = Folders::new();
    // A file longer than its buffer loads (src/scene/gltf/buffers.rs checks that only the
    // declared bytes are read); its name is percent-escaped in the URI.
    let long = [triangle_bytes(), vec![0xFF; 1000]].concat();
    std::fs::write(folders.scene().join("my tri.bin"), long).unwrap();
    let scene = folders.load("my%20tri.bin", 36).expect("a buffer file inside the folder");
    assert_eq!(scene.triangle_count(), 1);
    std::fs::write(folders.scene().join("sub/tri.bin"), triangle_bytes()).unwrap();
    assert!(folders.load("sub/../sub/tri.bin", 36).is_ok(), "a `..` that stays inside");
}

#[test]
fn buffer_paths_that_leave_the_folder_are_refused_before_opening() {
    let folders = Folders::new();
    let outside = folders.outside().display().to_string();
    for (uri, says) in [
        ("../outside.bin", "leaves the folder"),
        ("sub/../../outside.bin", "leaves the folder"),
        ("..%2Foutside.bin", "leaves the folder"),
        (outside.as_str(), "is an absolute path"),
        ("/dev/zero", "is an absolute path"),
    ] {
        let message = folders.refused(uri, 36, "buffers[0].uri");
        assert!(message.contains(says), "{uri}: {message}");
    }
}

/// An embedded buffer is held to `byteLength` as a file is: a `data:` URI of more base64 digits
/// than its declared bytes take is refused before it is decoded; one of exactly those loads.
#[test]
fn a_data_uri_longer_than_its_byte_length_is_refused() {
    const DIGITS: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let base64 = |bytes: &[u8]| -> String {
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | (b as u32) << (16 - 8 * i));
            for k in 0..=chunk.len() {
                out.push(DIGITS[(n >> (18 - 6 * k) & 63) as usize] as char);
            }
        }
        out
    };
    let folders = Folders::new();
    let uri = format!("data:application/octet-stream;base64,{}", base64(&triangle_bytes()));
    assert!(folders.load(&uri, 36).is_ok(), "the triangle's own 36 bytes load");
    let padded = [triangle_bytes(), vec![0; 300]].concat();
    let long_uri = format!("data:application/octet-stream;base64,{}", base64(&padded));
    let message = folders.refused(&long_uri, 36, "buffers[0].uri");
    assert!(message.contains("hold more than the 36 bytes of byteLength"), "{message}");
}

#[test]
fn a_buffer_file_shorter_than_declared_is_refused_by_its_length() {
    let folders = Folders::new();
    std::fs::write(folders.scene().join("short.bin"), &triangle_bytes()[..30]).unwrap();
    let message = folders.refused("short.bin", 36, "buffers[0].uri");
    assert!(message.contains("is 30 bytes, fewer than the buffer's byteLength 36"), "{message}");
    assert!(message.contains("short.bin"), "{message}");
}

/// The declared lengths together are checked before any file is looked at: the file named here
/// does not exist, and the problem is the size, not the missing file.
#[test]
fn buffers_declaring_more_than_the_limit_are_refused_before_reading() {
    let folders = Folders::new();
    let message = folders.refused("missing.bin", 3 << 30, "buffers[0].byteLength");
    assert!(message.contains("over the 2147483648"), "{message}");
}

/// A sparse file of 6 GB (no disk used) behind a buffer of 168 bytes: refused from its metadata
/// before a byte is read (the size check answers, not a read).
#[test]
fn a_huge_buffer_file_is_refused_by_its_size() {
    let folders = Folders::new();
    let huge = std::fs::File::create(folders.scene().join("huge.bin")).unwrap();
    huge.set_len(6 << 30).unwrap();
    let message = folders.refused("huge.bin", 168, "buffers[0].uri");
    assert!(message.contains("huge.bin is 6442450944 bytes, more than the 2147483648"), "{message}");
}

#[cfg(unix)]
#[test]
fn fifos_devices_and_links_out_of_the_folder_are_refused() {
    use std::os::unix::fs::symlink;
    let folders = Folders::new();
    let scene = folders.scene();
    symlink(folders.outside(), scene.join("link.bin")).unwrap();
    let message = folders.refused("link.bin", 36, "buffers[0].uri");
    assert!(message.contains("symbolic link"), "{message}");
    symlink("/dev/zero", scene.join("zero.bin")).unwrap();
    let message = folders.refused("zero.bin", 36, "buffers[0].uri");
    assert!(message.contains("a character device"), "{message}");
    // Opening a FIFO would wait for a writer forever: it is refused from its metadata.
    let status = std::process::Command::new("mkfifo").arg(scene.join("pipe.bin")).status().unwrap();
    assert!(status.success());
    let message = folders.refused("pipe.bin", 36, "buffers[0].uri");
    assert!(message.contains("a FIFO"), "{message}");
    // A link that stays inside the folder is followed.
    std::fs::write(scene.join("sub/tri.bin"), triangle_bytes()).unwrap();
    symlink(scene.join("sub/tri.bin"), scene.join("inner.bin")).unwrap();
    assert!(folders.load("inner.bin", 36).is_ok());
}

/// A scene file's glTF object: its buffers resolve in the glTF's folder, under the same rules,
/// and the problem is reported at the object with the glTF's own path.
#[test]
fn a_gltf_object_of_a_scene_file_reads_its_buffers_under_the_same_rules() {
    let folders = Folders::new();
    let scene = folders.scene();
    std::fs::write(scene.join("sub/model.gltf"), gltf_text("../../outside.bin", 36)).unwrap();
    let text = r#"{ "format": "shadowtruth/scene/v1", "name": "s",
        "objects": [{ "name": "m", "gltf": "sub/model.gltf" }],
        "cameras": [{ "name": "c", "position": [0, 2, 2], "look_at": [0, 0, 0], "up": [0, 1, 0],
                      "fov_y_deg": 50, "width": 8, "height": 8 }],
        "lights": [{ "name": "l", "type": "directional", "direction": [0, -1, 0] }] }"#;
    let problems =
        load_scene_str(text, &scene.join("s.json"), &scene).expect_err("a buffer outside").problems;
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].path, "objects[0].gltf");
    let message = &problems[0].message;
    assert!(message.contains("buffers[0].uri") && message.contains("leaves the folder"), "{message}");
    assert!(!message.contains("SECRET"), "{message}");
}
