//! SWC text → raw samples (stage 0).
//!
//! SWC is seven columns per sample: `id type x y z radius parent`. Real files are
//! untidy, so the reader is tolerant of everything that does not change meaning
//! and strict about everything that does:
//!
//! * tolerated: `#` comment lines anywhere (with any bytes in them), trailing `#`
//!   comments, a byte-order mark at the start of any line (files concatenated
//!   from several carry one per part), CRLF and CR line ends, tabs, commas or runs of spaces as
//!   separators, extra columns, ids written as `12.0`, any type code, any
//!   negative parent as "root", ids in any order and parents listed after their
//!   children;
//! * rejected with the 1-based line and a reason: fewer than seven fields, a field
//!   that is not a number, NaN or infinity, a fractional id, type or parent, a
//!   duplicate id (naming the first line too), an id beyond the integers an f64
//!   holds exactly (2^53), bytes no text holds (a binary file) and a file
//!   without a single sample. Quoted fields are cut to a few dozen characters.
//!
//! Tree-level problems (a parent that does not exist, a cycle) need the whole
//! file and are reported by [`crate::Morphology`], also with a line number.
//!
//! The reader works on bytes and allocates nothing per line; a 66k-line file
//! parses in a few milliseconds.

use std::collections::HashMap;
use std::path::Path;

use crate::error::{Error, Result};

/// One sample exactly as the file states it (units are the file's own).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawSample {
    /// The SWC id (column 1).
    pub id: i64,
    /// The SWC type code (column 2): 1 soma, 2 axon, 3 basal, 4 apical, others custom.
    pub kind: i32,
    /// Position (columns 3–5).
    pub pos: [f64; 3],
    /// Radius (column 6), unchecked: zero and negative radii are cleaned later.
    pub radius: f64,
    /// Parent id (column 7); negative means "root".
    pub parent: i64,
    /// 1-based line number in the file, for error messages.
    pub line: u32,
}

/// The samples of one SWC file plus the name used in error messages.
#[derive(Debug, Clone)]
pub struct SwcFile {
    /// The file as the user named it (or `<arrays>`).
    pub path: String,
    /// Samples in file order.
    pub samples: Vec<RawSample>,
    /// Number of comment lines (for `neuromesh info`).
    pub comment_lines: usize,
}

impl SwcFile {
    /// Reads and parses an SWC file: gzip-compressed (`.swc.gz`, known by
    /// its first bytes) or not, and `-` for standard input (named
    /// [`STDIN`] in messages).
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read, [`Error::Swc`] with the line and
    /// reason if it is malformed (line 1 for a broken gzip stream, or one
    /// that unpacks to more than [`MAX_UNPACKED`] bytes).
    pub fn read(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let (bytes, name) = if path == Path::new("-") {
            let mut bytes = Vec::new();
            std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)
                .map_err(|e| Error::io(path, e))?;
            (bytes, STDIN.to_owned())
        } else {
            let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
            (bytes, path.display().to_string())
        };
        if bytes.starts_with(&GZIP_MAGIC) {
            return Self::parse(&gunzip(&bytes, &name)?, &name);
        }
        Self::parse(&bytes, &name)
    }

    /// Parses SWC text held in memory; `name` is used in error messages.
    ///
    /// # Errors
    /// [`Error::Swc`] with the 1-based line and the reason.
    pub fn parse(bytes: &[u8], name: &str) -> Result<Self> {
        let mut samples = Vec::with_capacity(bytes.len() / 40);
        let mut comment_lines = 0usize;
        let mut line_no = 0usize;
        // The last line that holds anything: where "no samples" points.
        let mut last_line = 0usize;
        // Lines end with LF (CRLF leaves a CR that counts as white space),
        // or, in old Mac files, with CR alone. A final line end does not
        // start another line.
        let end = if bytes.contains(&b'\n') { b'\n' } else { b'\r' };
        let text = bytes.strip_suffix(&[end]).unwrap_or(bytes);
        for raw_line in text.split(|&b| b == end) {
            line_no += 1;
            // A byte-order mark can start the file and, in files
            // concatenated from several, any line.
            let raw_line = raw_line.strip_prefix(BOM).unwrap_or(raw_line);
            if !raw_line.iter().all(|b| b.is_ascii_whitespace()) {
                last_line = line_no;
            }
            if raw_line.contains(&0) {
                return Err(Error::swc(
                    name,
                    line_no,
                    "NUL byte found: this looks like a binary file, not SWC text",
                ));
            }
            // A trailing `#` comment ends the data part of the line.
            let data = match raw_line.iter().position(|&b| b == b'#') {
                Some(0) => {
                    comment_lines += 1;
                    continue;
                }
                Some(p) => &raw_line[..p],
                None => raw_line,
            };
            if data.iter().all(|b| b.is_ascii_whitespace()) {
                if raw_line.first() != Some(&b'#') && raw_line.contains(&b'#') {
                    comment_lines += 1;
                }
                continue;
            }
            if let Some(b) = binary_byte(data) {
                return Err(Error::swc(
                    name,
                    line_no,
                    format!(
                        "byte 0x{b:02X} is not text: this looks like a binary file, not SWC text"
                    ),
                ));
            }
            samples.push(parse_line(data, name, line_no)?);
        }
        if samples.is_empty() {
            return Err(Error::swc(
                name,
                last_line.max(1),
                if last_line == 0 {
                    "no samples: the file is empty"
                } else {
                    "no samples: the file has only comments and blank lines"
                },
            ));
        }
        check_unique_ids(&samples, name)?;
        Ok(SwcFile {
            path: name.to_owned(),
            samples,
            comment_lines,
        })
    }
}

/// The UTF-8 byte-order mark.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// The name standard input goes by in messages (`-` as a path reads it).
pub const STDIN: &str = "<stdin>";

/// The first bytes of a gzip stream: a `.swc.gz` file (or one piped in).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// A gzip stream unpacks to at most this many bytes: an SWC file of a
/// million samples is about 60 MB, and a stream that unpacks to more is
/// refused before it fills the memory.
pub const MAX_UNPACKED: u64 = 1 << 30;

/// `bytes` (a gzip stream, possibly of several members) unpacked.
fn gunzip(bytes: &[u8], name: &str) -> Result<Vec<u8>> {
    use std::io::Read;
    let mut out = Vec::with_capacity(bytes.len() * 4);
    let mut decoder = flate2::read::MultiGzDecoder::new(bytes).take(MAX_UNPACKED + 1);
    decoder
        .read_to_end(&mut out)
        .map_err(|e| Error::swc(name, 1, format!("not a valid gzip stream: {e}")))?;
    if out.len() as u64 > MAX_UNPACKED {
        return Err(Error::swc(
            name,
            1,
            format!(
                "the gzip stream unpacks to more than {} MiB",
                MAX_UNPACKED >> 20
            ),
        ));
    }
    Ok(out)
}

/// Fields quoted in messages are cut to this many characters: a line of
/// megabytes must not become a message of megabytes.
const QUOTED: usize = 40;

/// The first byte that no text holds in the data part of a line (comments
/// may hold anything and are not checked): a control character other than
/// whitespace, or a byte that is not UTF-8. Text that merely is not a
/// number is left to the field's own message.
fn binary_byte(data: &[u8]) -> Option<u8> {
    if let Some(&b) = data
        .iter()
        .find(|&&b| (b < 0x20 && !b.is_ascii_whitespace()) || b == 0x7F)
    {
        return Some(b);
    }
    std::str::from_utf8(data)
        .err()
        .map(|e| data[e.valid_up_to()])
}

/// A field as quoted in a message, cut to [`QUOTED`] characters.
fn quoted(field: &[u8]) -> String {
    let text = String::from_utf8_lossy(field);
    if text.chars().count() <= QUOTED {
        text.into_owned()
    } else {
        let cut: String = text.chars().take(QUOTED).collect();
        format!("{cut}… ({} bytes)", field.len())
    }
}

/// The largest integer that an f64 (every number in an SWC file is read as
/// one) holds exactly: 2^53.
const EXACT_INTEGERS: f64 = 9_007_199_254_740_992.0;

fn parse_line(data: &[u8], name: &str, line: usize) -> Result<RawSample> {
    let mut fields: [&[u8]; 7] = [&[]; 7];
    let mut n = 0usize;
    for field in data
        .split(|&b| b.is_ascii_whitespace() || b == b',')
        .filter(|f| !f.is_empty())
    {
        if n < 7 {
            fields[n] = field;
        }
        n += 1;
    }
    if n < 7 {
        return Err(Error::swc(
            name,
            line,
            format!("expected 7 fields (id type x y z radius parent), found {n}"),
        ));
    }
    const NAMES: [&str; 7] = ["id", "type", "x", "y", "z", "radius", "parent"];
    let mut values = [0f64; 7];
    for (i, field) in fields.iter().enumerate() {
        values[i] = parse_number(field).ok_or_else(|| {
            Error::swc(
                name,
                line,
                format!("{} is not a number: `{}`", NAMES[i], quoted(field)),
            )
        })?;
        if !values[i].is_finite() {
            return Err(Error::swc(
                name,
                line,
                format!("{} must be finite, found `{}`", NAMES[i], quoted(field)),
            ));
        }
    }
    let integer = |i: usize| -> Result<i64> {
        let v = values[i];
        if v.abs() >= EXACT_INTEGERS {
            return Err(Error::swc(
                name,
                line,
                format!(
                    "{} `{}` is beyond the integers a 64-bit float holds exactly (±2^53)",
                    NAMES[i],
                    quoted(fields[i])
                ),
            ));
        }
        if v.fract() != 0.0 {
            return Err(Error::swc(
                name,
                line,
                format!(
                    "{} must be an integer, found `{}`",
                    NAMES[i],
                    quoted(fields[i])
                ),
            ));
        }
        Ok(v as i64)
    };
    let id = integer(0)?;
    let kind = integer(1)?;
    let parent = integer(6)?;
    if id < 0 {
        return Err(Error::swc(
            name,
            line,
            format!("id must not be negative, found {id}"),
        ));
    }
    Ok(RawSample {
        id,
        kind: kind.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
        pos: [values[2], values[3], values[4]],
        radius: values[5],
        parent: if parent < 0 { -1 } else { parent },
        line: u32::try_from(line).unwrap_or(u32::MAX),
    })
}

/// Parses a decimal number; `None` for anything that is not one (including
/// non-UTF-8 bytes).
fn parse_number(field: &[u8]) -> Option<f64> {
    let text = std::str::from_utf8(field).ok()?;
    // Rust accepts "inf"/"nan" spellings; they are caught as non-finite by the caller.
    text.parse::<f64>().ok()
}

fn check_unique_ids(samples: &[RawSample], name: &str) -> Result<()> {
    IdIndex::new(samples.iter().map(|s| s.id))
        .map(|_| ())
        .map_err(|(second, first)| {
            Error::swc(
                name,
                samples[second].line as usize,
                format!(
                    "duplicate id {} (first defined on line {})",
                    samples[second].id, samples[first].line
                ),
            )
        })
}

/// Sample ids to their positions in the file. Tracing tools number samples
/// 1, 2, 3...: ids spanning at most a few times their count go in an array,
/// a few times faster than a map; scattered ids in a map, SipHash since the
/// ids are the file's.
pub(crate) enum IdIndex {
    /// `slot[id - min]` is the position of `id`, or `u32::MAX`.
    Dense {
        min: i64,
        slot: Vec<u32>,
    },
    Sparse(HashMap<i64, u32>),
}

impl IdIndex {
    /// The index of `ids`, or the positions of the first repeated id and of
    /// its first occurrence.
    pub(crate) fn new(
        ids: impl ExactSizeIterator<Item = i64> + Clone,
    ) -> std::result::Result<IdIndex, (usize, usize)> {
        let n = ids.len();
        let (min, max) = ids.clone().fold((i64::MAX, i64::MIN), |(lo, hi), id| {
            (lo.min(id), hi.max(id))
        });
        let span = (max as i128 - min as i128 + 1).max(0) as u128;
        if n > 0 && span <= 4 * n as u128 + 64 {
            let mut slot = vec![u32::MAX; span as usize];
            for (i, id) in ids.enumerate() {
                let at = &mut slot[(id - min) as usize];
                if *at != u32::MAX {
                    return Err((i, *at as usize));
                }
                *at = i as u32;
            }
            return Ok(IdIndex::Dense { min, slot });
        }
        let mut map = HashMap::with_capacity(n);
        for (i, id) in ids.enumerate() {
            if let Some(&first) = map.get(&id) {
                return Err((i, first as usize));
            }
            map.insert(id, i as u32);
        }
        Ok(IdIndex::Sparse(map))
    }

    /// The position of `id`, if a sample has it.
    pub(crate) fn get(&self, id: i64) -> Option<u32> {
        match self {
            IdIndex::Dense { min, slot } => {
                let k = usize::try_from(id.checked_sub(*min)?).ok()?;
                slot.get(k).copied().filter(|&i| i != u32::MAX)
            }
            IdIndex::Sparse(map) => map.get(&id).copied(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SwcFile> {
        SwcFile::parse(text.as_bytes(), "t.swc")
    }

    fn err_line(text: &str) -> (usize, String) {
        match parse(text) {
            Err(Error::Swc(e)) => (e.line, e.reason),
            other => panic!("expected an SWC error, got {other:?}"),
        }
    }

    #[test]
    fn reads_comments_crlf_tabs_commas_and_extra_columns() {
        let f = parse("# header \u{fffd}\r\n1 1 0 0 0 5 -1\r\n2\t3\t1\t0\t0\t1\t1 extra\r\n3,3,2,0,0,1,2 # trailing\n\n")
            .unwrap();
        assert_eq!(f.samples.len(), 3);
        assert_eq!(f.samples[1].kind, 3);
        assert_eq!(f.samples[2].pos, [2.0, 0.0, 0.0]);
        assert_eq!(f.samples[2].line, 4);
        assert_eq!(f.comment_lines, 1);
    }

    #[test]
    fn accepts_integral_floats_and_any_negative_parent() {
        let f = parse("1.0 1 0 0 0 1 -2\n2 3.0 0 0 1 1 1.0\n").unwrap();
        assert_eq!(f.samples[0].parent, -1);
        assert_eq!(f.samples[1].parent, 1);
    }

    #[test]
    fn too_few_fields() {
        let (line, reason) = err_line("1 1 0 0 0 1 -1\n2 3 0 0\n");
        assert_eq!(line, 2);
        assert!(reason.contains("expected 7 fields"), "{reason}");
    }

    #[test]
    fn not_a_number() {
        let (line, reason) = err_line("# c\n1 1 0 zero 0 1 -1\n");
        assert_eq!(line, 2);
        assert!(reason.contains("y is not a number"), "{reason}");
    }

    #[test]
    fn nan_and_infinity() {
        let (line, reason) = err_line("1 1 0 0 0 NaN -1\n");
        assert_eq!(line, 1);
        assert!(reason.contains("radius must be finite"), "{reason}");
        let (line, _) = err_line("1 1 0 0 0 1 -1\n2 1 inf 0 0 1 1\n");
        assert_eq!(line, 2);
    }

    #[test]
    fn fractional_id() {
        let (_, reason) = err_line("1.5 1 0 0 0 1 -1\n");
        assert!(reason.contains("id must be an integer"), "{reason}");
    }

    #[test]
    fn the_id_index_finds_every_id_dense_or_scattered() {
        // Numbered from 1 with gaps (an array), and scattered (a map).
        for ids in [
            vec![1i64, 2, 3, 7, 5, -1],
            vec![10, -1_000_000_000_000, 3, 1 << 40],
        ] {
            let index = IdIndex::new(ids.iter().copied()).expect("unique");
            assert_eq!(
                matches!(index, IdIndex::Dense { .. }),
                ids[1] == 2,
                "which kind"
            );
            for (i, &id) in ids.iter().enumerate() {
                assert_eq!(index.get(id), Some(i as u32), "id {id}");
            }
            for absent in [0i64, 4, 6, 8, i64::MIN, i64::MAX, 11] {
                assert_eq!(index.get(absent), None, "id {absent}");
            }
        }
        // A repeat names itself and the first occurrence, either way.
        assert_eq!(
            IdIndex::new([1i64, 2, 3, 2].into_iter()).err(),
            Some((3, 1))
        );
        assert_eq!(
            IdIndex::new([9i64, 1 << 50, 9].into_iter()).err(),
            Some((2, 0))
        );
    }

    #[test]
    fn duplicate_id_names_both_lines() {
        let (line, reason) = err_line("1 1 0 0 0 1 -1\n2 3 0 0 1 1 1\n2 3 0 0 2 1 1\n");
        assert_eq!(line, 3);
        assert!(
            reason.contains("duplicate id 2 (first defined on line 2)"),
            "{reason}"
        );
    }

    #[test]
    fn empty_and_comment_only_files() {
        let (line, reason) = err_line("");
        assert_eq!(line, 1);
        assert!(reason.contains("no samples"));
        // The last line that holds something, not the end of the file.
        let (line, reason) = err_line("# a\n# b\n\n");
        assert_eq!(line, 2);
        assert!(reason.contains("only comments"), "{reason}");
    }

    #[test]
    fn byte_order_marks_before_comments_and_samples() {
        let f = parse("\u{feff}# header\n1 1 0 0 0 5 -1\n\u{feff}2 3 1 0 0 1 1\n").unwrap();
        assert_eq!(f.samples.len(), 2);
        assert_eq!(f.comment_lines, 1);
        assert_eq!(f.samples[1].line, 3);
    }

    #[test]
    fn cr_only_line_ends() {
        let f = parse("# old Mac\r1 1 0 0 0 5 -1\r2 3 1 0 0 1 1\r").unwrap();
        assert_eq!(f.samples.len(), 2);
        assert_eq!(f.samples[1].line, 3);
    }

    #[test]
    fn an_image_renamed_swc_is_called_binary() {
        let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
        match SwcFile::parse(png, "cell.swc") {
            Err(Error::Swc(e)) => {
                assert_eq!(e.line, 1);
                assert!(e.reason.contains("binary"), "{}", e.reason);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn long_fields_are_cut_in_messages() {
        let long = "x".repeat(100_000);
        let (_, reason) = err_line(&format!("1 1 {long} 0 0 1 -1\n"));
        assert!(reason.len() < 120, "{} bytes", reason.len());
        assert!(reason.contains("100000 bytes"), "{reason}");
    }

    #[test]
    fn ids_beyond_exact_integers_say_so() {
        let (_, reason) = err_line("1e16 1 0 0 0 1 -1\n");
        assert!(reason.contains("2^53"), "{reason}");
        let f = parse("9007199254740991 1 0 0 0 1 -1\n").unwrap();
        assert_eq!(f.samples[0].id, 9_007_199_254_740_991);
    }

    #[test]
    fn binary_file() {
        let bytes = b"1 1 0 0 0 1 -1\n\x7fELF\x02\x01\x00\x00\n";
        match SwcFile::parse(bytes, "b.swc") {
            Err(Error::Swc(e)) => {
                assert_eq!(e.line, 2);
                assert!(e.reason.contains("binary"));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn non_utf8_in_data_is_binary() {
        let bytes = b"1 1 0 0 0 1 -1\n2 3 \xff\xfe 0 0 1 1\n";
        match SwcFile::parse(bytes, "b.swc") {
            Err(Error::Swc(e)) => {
                assert_eq!(e.line, 2);
                assert!(e.reason.contains("0xFF"), "{}", e.reason);
            }
            other => panic!("{other:?}"),
        }
        // UTF-8 that is not a number gets the field's own message.
        let (line, reason) = err_line("1 1 0 0 0 1 -1\n2 3 1\u{2212}2 0 0 1 1\n");
        assert_eq!(line, 2);
        assert!(reason.contains("x is not a number"), "{reason}");
    }

    #[test]
    fn a_gzip_file_reads_as_its_text_and_a_broken_one_is_refused() {
        use std::io::Write;
        let text = "# c\n1 1 0 0 0 5 -1\n2 3 10 0 0 1 1\n";
        let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(text.as_bytes()).unwrap();
        let packed = z.finish().unwrap();
        let dir = std::env::temp_dir().join(format!("neuromesh-gz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("cell.swc.gz");
        std::fs::write(&path, &packed).unwrap();
        let read = SwcFile::read(&path).unwrap();
        assert_eq!(read.samples, parse(text).unwrap().samples);
        // Cut short: an error at line 1 naming the file.
        std::fs::write(&path, &packed[..packed.len() / 2]).unwrap();
        match SwcFile::read(&path) {
            Err(Error::Swc(e)) => {
                assert_eq!(e.line, 1);
                assert!(e.reason.contains("gzip"), "{}", e.reason);
                assert_eq!(e.path, path.display().to_string());
            }
            other => panic!("{other:?}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
