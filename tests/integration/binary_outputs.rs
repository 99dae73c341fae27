//! The binary outputs, `packing.vtp` and `packing.npz`, read back by small
//! independent readers written here (XML attributes and the appended
//! block; the zip's central directory, local headers and CRC-32, and each
//! `.npy` header) and compared with `packing.csv` value for value, bit for
//! bit: the CSV holds shortest round-trip numbers, which parse back to the
//! same `f64`.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use crate::common::{gapack, scratch};

/// `packing.csv`: the header and each row's cells.
struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Csv {
    fn read(path: &Path) -> Csv {
        let text = fs::read_to_string(path).expect("packing.csv");
        let mut lines = text.lines();
        let header = lines
            .next()
            .expect("a header")
            .split(',')
            .map(str::to_owned)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect();
        Csv { header, rows }
    }

    fn has(&self, name: &str) -> bool {
        self.header.iter().any(|h| h == name)
    }

    /// Column `name` as text, one cell per row.
    fn column(&self, name: &str) -> Vec<&str> {
        let k = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[k].as_str()).collect()
    }

    /// Column `name` as the bits of its numbers; an empty cell is NaN.
    fn f64_bits(&self, name: &str) -> Vec<u64> {
        self.column(name)
            .iter()
            .map(|c| {
                if c.is_empty() {
                    f64::NAN.to_bits()
                } else {
                    c.parse::<f64>()
                        .unwrap_or_else(|_| panic!("{name}: not a number {c:?}"))
                        .to_bits()
                }
            })
            .collect()
    }
}

/// An array read back: its type's name and its values as 64-bit patterns
/// (an `f64`'s bits, an integer sign-extended).
#[derive(Debug, PartialEq)]
struct Values {
    kind: String,
    bits: Vec<u64>,
}

/// Little-endian values of `size` bytes, as [`Values::bits`].
fn decode(bytes: &[u8], kind: &str) -> Vec<u64> {
    match kind {
        "f8" | "i8" => bytes
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
            .collect(),
        "i4" => bytes
            .chunks_exact(4)
            .map(|c| i64::from(i32::from_le_bytes(c.try_into().unwrap())) as u64)
            .collect(),
        other => panic!("unexpected type {other}"),
    }
}

fn le64(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}
fn le32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}
fn le16(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes(b[at..at + 2].try_into().unwrap())
}

/// The value of attribute `name` in an XML start tag.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    let len = tag[at..].find('"')?;
    Some(&tag[at..at + len])
}

/// `packing.vtp`: the number of points and each `DataArray` by name,
/// after checking the file's attributes and the appended block's layout.
fn read_vtp(path: &Path) -> (usize, BTreeMap<String, (usize, Values)>) {
    let bytes = fs::read(path).expect("packing.vtp");
    let open = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(open.len())
        .position(|w| w == open)
        .expect("an appended block");
    let head = std::str::from_utf8(&bytes[..at]).expect("an XML head");
    let marker = at
        + open.len()
        + bytes[at + open.len()..]
            .iter()
            .position(|&b| b == b'_')
            .expect("the _ marker");
    let base = marker + 1;
    let file = head.find("<VTKFile").map(|i| &head[i..]).expect("VTKFile");
    assert_eq!(attr(file, "type"), Some("PolyData"));
    assert_eq!(attr(file, "version"), Some("1.0"));
    assert_eq!(attr(file, "byte_order"), Some("LittleEndian"));
    assert_eq!(attr(file, "header_type"), Some("UInt64"));
    let zlib = match attr(file, "compressor") {
        None => false,
        Some(c) => {
            assert_eq!(c, "vtkZLibDataCompressor");
            true
        }
    };
    let piece = &head[head.find("<Piece").expect("a piece")..];
    let n: usize = attr(piece, "NumberOfPoints").unwrap().parse().unwrap();
    assert_eq!(attr(piece, "NumberOfVerts"), Some(n.to_string().as_str()));
    let mut arrays = BTreeMap::new();
    let mut end = base;
    for tag in head.split("<DataArray").skip(1) {
        let tag = &tag[..tag.find("/>").expect("an empty element")];
        assert_eq!(attr(tag, "format"), Some("appended"));
        let name = attr(tag, "Name").unwrap().to_owned();
        let components: usize = attr(tag, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
        let offset: usize = attr(tag, "offset").unwrap().parse().unwrap();
        let (kind, size) = match attr(tag, "type").unwrap() {
            "Float64" => ("f8", 8),
            "Int32" => ("i4", 4),
            "Int64" => ("i8", 8),
            other => panic!("{name}: unexpected type {other}"),
        };
        let start = base + offset;
        let (data, stop) = if zlib {
            inflate_blocks(&bytes, start, n * components * size, &name)
        } else {
            let count = le64(&bytes, start) as usize;
            assert_eq!(count, n * components * size, "{name}: byte count");
            (
                bytes[start + 8..start + 8 + count].to_vec(),
                start + 8 + count,
            )
        };
        let data = &data[..];
        end = end.max(stop);
        let values = Values {
            kind: kind.to_owned(),
            bits: decode(data, kind),
        };
        assert!(arrays.insert(name, (components, values)).is_none());
    }
    assert_eq!(
        std::str::from_utf8(&bytes[end..]).expect("a tail"),
        "\n  </AppendedData>\n</VTKFile>\n",
        "the arrays end where the block does"
    );
    (n, arrays)
}

/// A zlib-compressed appended array at `start`, as VTK reads it: the
/// UInt64 header (blocks, block size, partial last block size or 0, each
/// block's compressed size), then the blocks, each inflated on its own;
/// its values (`count` bytes) and the byte after it.
fn inflate_blocks(bytes: &[u8], start: usize, count: usize, name: &str) -> (Vec<u8>, usize) {
    use std::io::Read;
    let blocks = le64(bytes, start) as usize;
    let block = le64(bytes, start + 8) as usize;
    let last = le64(bytes, start + 16) as usize;
    assert_eq!(block, 32_768, "{name}: VTK's block size");
    assert_eq!(blocks, count.div_ceil(block), "{name}: blocks");
    assert_eq!(last, count % block, "{name}: the last block's size");
    let sizes: Vec<usize> = (0..blocks)
        .map(|b| le64(bytes, start + 24 + 8 * b) as usize)
        .collect();
    let mut at = start + 24 + 8 * blocks;
    let mut data = Vec::with_capacity(count);
    for (b, &size) in sizes.iter().enumerate() {
        let mut part = Vec::new();
        flate2::read::ZlibDecoder::new(&bytes[at..at + size])
            .read_to_end(&mut part)
            .expect("a zlib stream");
        let want = if b + 1 == blocks && last != 0 {
            last
        } else {
            block
        };
        assert_eq!(part.len(), want, "{name}: block {b}");
        data.extend(part);
        at += size;
    }
    assert_eq!(data.len(), count, "{name}: byte count");
    (data, at)
}

/// CRC-32 (IEEE, reflected), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// One `.npy` file: its dtype (`f8`, `i4`) and values, after checking its
/// header says version 1.0, little-endian, C order and one dimension.
fn read_npy(name: &str, b: &[u8]) -> (usize, Values) {
    assert_eq!(&b[..8], b"\x93NUMPY\x01\x00", "{name}: magic and version");
    let len = usize::from(le16(b, 8));
    assert_eq!((10 + len) % 64, 0, "{name}: the data aligned");
    let dict = std::str::from_utf8(&b[10..10 + len]).expect("an ASCII header");
    assert!(dict.ends_with('\n'));
    assert!(dict.contains("'fortran_order': False"), "{dict}");
    let descr = dict.split("'descr': '").nth(1).unwrap();
    let descr = &descr[..descr.find('\'').unwrap()];
    let kind = descr.strip_prefix('<').expect("little-endian");
    let shape = dict.split("'shape': (").nth(1).unwrap();
    let shape = &shape[..shape.find(')').unwrap()];
    let n: usize = shape
        .strip_suffix(',')
        .expect("one dimension")
        .parse()
        .unwrap();
    let data = &b[10 + len..];
    let size = if kind == "i4" { 4 } else { 8 };
    assert_eq!(data.len(), n * size, "{name}: data size");
    let values = Values {
        kind: kind.to_owned(),
        bits: decode(data, kind),
    };
    (n, values)
}

/// `packing.npz`: each `.npy` by name (without `.npy`), in archive order,
/// after checking the end record, the central directory, each local
/// header (stored, no data descriptor, the same sizes and CRC) and the CRC.
fn read_npz(path: &Path) -> Vec<(String, Values)> {
    let b = fs::read(path).expect("packing.npz");
    let eocd = b.len() - 22;
    assert_eq!(le32(&b, eocd), 0x0605_4b50, "an end record without comment");
    let count = usize::from(le16(&b, eocd + 10));
    let cd_size = le32(&b, eocd + 12) as usize;
    let mut at = le32(&b, eocd + 16) as usize;
    assert_eq!(
        at + cd_size,
        eocd,
        "the central directory ends at the end record"
    );
    let mut out = Vec::new();
    for _ in 0..count {
        assert_eq!(le32(&b, at), 0x0201_4b50);
        let (method, crc) = (le16(&b, at + 10), le32(&b, at + 16));
        let (csize, usize_) = (le32(&b, at + 20) as usize, le32(&b, at + 24) as usize);
        let (nlen, xlen, clen) = (
            usize::from(le16(&b, at + 28)),
            usize::from(le16(&b, at + 30)),
            usize::from(le16(&b, at + 32)),
        );
        let local = le32(&b, at + 42) as usize;
        let name = std::str::from_utf8(&b[at + 46..at + 46 + nlen])
            .unwrap()
            .to_owned();
        at += 46 + nlen + xlen + clen;
        assert_eq!(method, 0, "{name}: stored");
        assert_eq!(csize, usize_, "{name}: stored");
        assert_eq!(le32(&b, local), 0x0403_4b50);
        assert_eq!(le16(&b, local + 6) & 0x8, 0, "{name}: no data descriptor");
        assert_eq!(le32(&b, local + 14), crc);
        assert_eq!(le32(&b, local + 18) as usize, csize);
        let (lnlen, lxlen) = (
            usize::from(le16(&b, local + 26)),
            usize::from(le16(&b, local + 28)),
        );
        assert_eq!(&b[local + 30..local + 30 + lnlen], name.as_bytes());
        let start = local + 30 + lnlen + lxlen;
        let data = &b[start..start + csize];
        assert_eq!(crc32(data), crc, "{name}: CRC-32");
        let (_, values) = read_npy(&name, data);
        let stem = name.strip_suffix(".npy").expect("a .npy").to_owned();
        out.push((stem, values));
    }
    assert_eq!(at, eocd);
    out
}

/// The material index of each row: its name's place in `names` (0
/// without a `material` column).
fn materials(csv: &Csv, names: &[&str]) -> Vec<u64> {
    if !csv.has("material") {
        return vec![0; csv.rows.len()];
    }
    csv.column("material")
        .iter()
        .map(|m| names.iter().position(|n| n == m).expect("a known material") as u64)
        .collect()
}

/// `packing.vtp` and `packing.npz` of the run in `out` hold `packing.csv`
/// exactly (`names`: the config's materials, in order).
fn check_run(out: &Path, names: &[&str]) {
    let csv = Csv::read(&out.join("packing.csv"));
    let n = csv.rows.len();
    assert!(n > 20, "too few particles to test: {n}");
    let f8 = |bits: Vec<u64>| Values {
        kind: "f8".into(),
        bits,
    };
    let i4 = |bits: Vec<u64>| Values {
        kind: "i4".into(),
        bits,
    };
    // The shape columns packing.csv has, float64 but the template.
    let shapes: Vec<(&str, Values)> = ["angle", "a", "b", "alpha", "beta", "template", "rounding"]
        .into_iter()
        .filter(|c| csv.has(c))
        .map(|c| {
            let v = if c == "template" {
                i4(csv
                    .column(c)
                    .iter()
                    .map(|t| if t.is_empty() { -1i64 } else { t.parse().unwrap() } as u64)
                    .collect())
            } else {
                f8(csv.f64_bits(c))
            };
            (c, v)
        })
        .collect();
    let material = materials(&csv, names);
    // `[output] per_particle`: float64 columns after `material`.
    let extra: Vec<(&str, Values)> = ["h6"]
        .into_iter()
        .filter(|c| csv.has(c))
        .map(|c| (c, f8(csv.f64_bits(c))))
        .collect();

    let (points, vtp) = read_vtp(&out.join("packing.vtp"));
    assert_eq!(points, n);
    let get = |name: &str| &vtp.get(name).unwrap_or_else(|| panic!("vtp: no {name}")).1;
    let xyz = get("Points");
    assert_eq!(vtp["Points"].0, 3);
    let (x, y) = (csv.f64_bits("x"), csv.f64_bits("y"));
    for i in 0..n {
        assert_eq!(
            xyz.bits[3 * i..3 * i + 3],
            [x[i], y[i], 0.0f64.to_bits()],
            "point {i}"
        );
    }
    assert_eq!(*get("radius"), f8(csv.f64_bits("r")));
    let ids: Vec<u64> = csv
        .column("id")
        .iter()
        .map(|i| i.parse().unwrap())
        .collect();
    assert_eq!(ids, (0..n as u64).collect::<Vec<_>>());
    let int64 = |bits: Vec<u64>| Values {
        kind: "i8".into(),
        bits,
    };
    assert_eq!(*get("id"), int64(ids.clone()));
    assert_eq!(*get("connectivity"), int64(ids.clone()));
    assert_eq!(*get("offsets"), int64(ids.iter().map(|i| i + 1).collect()));
    assert_eq!(*get("material"), i4(material.clone()));
    for (name, values) in shapes.iter().chain(&extra) {
        assert_eq!(get(name), values, "vtp {name}");
    }
    let mut expected = vec![
        "Points",
        "connectivity",
        "id",
        "material",
        "offsets",
        "radius",
    ];
    expected.extend(shapes.iter().chain(&extra).map(|(c, _)| *c));
    expected.sort_unstable();
    assert_eq!(vtp.keys().map(String::as_str).collect::<Vec<_>>(), expected);

    let npz = read_npz(&out.join("packing.npz"));
    let mut want = vec![("x", f8(x)), ("y", f8(y)), ("r", f8(csv.f64_bits("r")))];
    want.extend(shapes);
    want.push(("material", i4(material)));
    want.extend(extra);
    let got: Vec<(&str, &Values)> = npz.iter().map(|(k, v)| (k.as_str(), v)).collect();
    let want: Vec<(&str, &Values)> = want.iter().map(|(k, v)| (*k, v)).collect();
    assert_eq!(got, want);
}

/// Runs `gapack command` on `config` in a scratch folder and checks its
/// binary outputs against its `packing.csv`.
fn run_and_check(name: &str, command: &str, config: &str, materials: &[&str]) -> Csv {
    run_and_check_with(name, command, config, materials, "")
}

/// [`run_and_check`] with more `[output]` keys (`extra`, whole lines).
fn run_and_check_with(
    name: &str,
    command: &str,
    config: &str,
    materials: &[&str],
    extra: &str,
) -> Csv {
    let dir = scratch(&format!("binary-{name}"));
    let text = format!("{config}\n[output]\nformats = [\"csv\", \"vtp\", \"npz\"]\n{extra}");
    fs::write(dir.join("c.toml"), text).unwrap();
    let out = gapack(&dir, &[command, "c.toml", "--out", "out"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let manifest = fs::read_to_string(dir.join("out/manifest.json")).unwrap();
    assert!(manifest.contains("packing.vtp") && manifest.contains("packing.npz"));
    check_run(&dir.join("out"), materials);
    Csv::read(&dir.join("out/packing.csv"))
}

/// A few scenes of disks drawn from a fixed seed: size of the domain, its
/// shape, the grading and the packing's seed.
#[test]
fn disk_packings_read_back_bit_for_bit() {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut draw = |lo: f64, hi: f64| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
    };
    for k in 0..3 {
        let (w, h) = (draw(8.0, 20.0), draw(8.0, 20.0));
        let (d0, d1) = (draw(0.5, 1.0), draw(1.2, 2.5));
        let seed = (draw(0.0, 1000.0)) as u64;
        let domain = if k == 1 {
            format!("shape = \"circle\"\nradius = {}", w.min(h) / 2.0)
        } else {
            format!("shape = \"rectangle\"\nwidth = {w}\nheight = {h}")
        };
        let config =
            format!("seed = {seed}\n[domain]\n{domain}\n[grading]\nuniform = [{d0}, {d1}]\n");
        let csv = run_and_check(&format!("disks-{k}"), "pack", &config, &[]);
        assert!(!csv.has("material") && !csv.has("angle"));
    }
}

/// `vtp_compression = "zlib"`: the arrays in zlib blocks as VTK writes
/// them, several blocks an array, read back bit for bit, for disks and
/// for superellipses with materials.
#[test]
fn a_zlib_vtp_reads_back_bit_for_bit() {
    let disks = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 40\n\
                 [grading]\nuniform = [0.6, 1.2]\n";
    let csv = run_and_check_with(
        "zlib-disks",
        "pack",
        disks,
        &[],
        "vtp_compression = \"zlib\"\n",
    );
    // Points take 24 bytes a disk: more than one block of 32768 bytes.
    assert!(csv.rows.len() * 24 > 2 * 32_768, "{} disks", csv.rows.len());
    let shapes = "seed = 6\n[domain]\nshape = \"rectangle\"\nwidth = 14\nheight = 10\n\
                  [grading]\nuniform = [1.0, 1.6]\n\
                  [shape]\nkind = \"superellipse\"\naspect = [1.2, 2.0]\norientation = \"random\"\n";
    run_and_check_with(
        "zlib-shapes",
        "pack",
        shapes,
        &[],
        "vtp_compression = \"zlib\"\n",
    );
}

/// Superellipses: `angle`, `a`, `b`, `alpha`, `beta` as in `packing.csv`,
/// `r` the area-equivalent radius.
#[test]
fn a_superellipse_packing_reads_back_bit_for_bit() {
    let config = "seed = 6\n[domain]\nshape = \"rectangle\"\nwidth = 14\nheight = 10\n\
                  [grading]\nuniform = [1.0, 1.6]\n\
                  [shape]\nkind = \"superellipse\"\naspect = [1.2, 2.0]\norientation = \"random\"\n";
    let csv = run_and_check("superellipses", "pack", config, &[]);
    assert!(csv.has("angle") && csv.has("beta"), "shape columns");
}

/// Two materials: `material` is each particle's index in the config's
/// list, as `packing.csv` names it.
#[test]
fn material_indices_follow_the_config() {
    let config = "seed = 11\n[domain]\nshape = \"rectangle\"\nwidth = 12\nheight = 12\n\
                  [grading]\nuniform = [1.0, 1.5]\n\
                  [[materials]]\nname = \"ceramic\"\ndensity = 3900\n\
                  [[materials]]\nname = \"hard metal\"\ndensity = 7800\n\
                  [layering]\naxis = \"y\"\nbins = 4\nprofile = \"steps\"\n\
                  layers = [[\"hard metal\", 0.5], [\"ceramic\", 0.5]]\n";
    let csv = run_and_check("materials", "layer", config, &["ceramic", "hard metal"]);
    let used = materials(&csv, &["ceramic", "hard metal"]);
    assert!(
        used.contains(&0) && used.contains(&1),
        "both materials packed"
    );
}

/// `per_particle = ["h6"]`: the last column of `packing.csv`, the rest of
/// the table as without it byte for byte, the same values in `packing.vtp`
/// and `packing.npz` (by [`check_run`]), each the distance to the 6th
/// nearest centre of the table, for disks and for superellipses.
#[test]
fn h6_is_the_last_column_and_the_sixth_nearest_centre() {
    let disks = "seed = 4\n[domain]\nshape = \"rectangle\"\nwidth = 16\nheight = 12\n\
                 [grading]\nuniform = [0.6, 1.4]\n";
    let shapes = "seed = 6\n[domain]\nshape = \"rectangle\"\nwidth = 14\nheight = 10\n\
                  [grading]\nuniform = [1.0, 1.6]\n\
                  [shape]\nkind = \"superellipse\"\naspect = [1.2, 2.0]\norientation = \"random\"\n";
    for (name, config) in [("h6-disks", disks), ("h6-shapes", shapes)] {
        let plain = run_and_check(&format!("{name}-plain"), "pack", config, &[]);
        let with = run_and_check_with(name, "pack", config, &[], "per_particle = [\"h6\"]\n");
        assert!(!plain.has("h6"));
        assert_eq!(with.header.last().map(String::as_str), Some("h6"));
        assert_eq!(with.header[..with.header.len() - 1], plain.header[..]);
        for (a, b) in plain.rows.iter().zip(&with.rows) {
            assert_eq!(b[..b.len() - 1], a[..]);
        }
        let (x, y) = (with.f64_bits("x"), with.f64_bits("y"));
        let c: Vec<(f64, f64)> = x
            .iter()
            .zip(&y)
            .map(|(&x, &y)| (f64::from_bits(x), f64::from_bits(y)))
            .collect();
        for (i, h6) in with.f64_bits("h6").into_iter().enumerate() {
            let mut d: Vec<f64> = (0..c.len())
                .filter(|&j| j != i)
                .map(|j| ((c[i].0 - c[j].0).powi(2) + (c[i].1 - c[j].1).powi(2)).sqrt())
                .collect();
            d.sort_by(f64::total_cmp);
            let h6 = f64::from_bits(h6);
            assert!(
                (h6 - d[5]).abs() <= 1e-12 * d[5],
                "{name}, particle {i}: {h6} against {}",
                d[5]
            );
        }
    }
}
