//! The `neuromesh` binary: shapes of its commands, exit codes and messages.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn neuromesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neuromesh"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("neuromesh-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn info_succeeds_on_every_real_file() {
    for f in common::real_files() {
        let out = neuromesh(&["info", f.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}: {}",
            f.display(),
            text(&out.stderr)
        );
        let s = text(&out.stdout);
        assert!(s.contains("samples") && s.contains("soma"), "{s}");
    }
}

#[test]
fn radii_in_another_unit_are_warned_about_and_still_succeed() {
    // The CAR platform's radius column holds codes (40 to 6,910) on a cell
    // about 200 units across; a Purkinje cell's radii are fine.
    let car = "tests/data/real/human_cortex_CAR_00148_P003_IPL.swc";
    let out = neuromesh(&["info", car]);
    assert!(out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.starts_with(&format!("warning: {car}: radii look implausible")),
        "{err}"
    );
    let out = neuromesh(&["info", "tests/data/real/purkinje_martone_alxP.CNG.swc"]);
    assert!(out.status.success());
    assert_eq!(text(&out.stderr), "");
}

#[test]
fn info_json_is_machine_readable() {
    let out = neuromesh(&["info", "tests/data/y_bifurcation.swc", "--json"]);
    assert!(out.status.success());
    let s = text(&out.stdout);
    assert!(
        s.trim_start().starts_with('{') && s.trim_end().ends_with('}'),
        "{s}"
    );
    assert!(s.contains("\"samples\":7"), "{s}");
    assert!(s.contains("\"branch_points\":{\"2\":1}"), "{s}");
}

#[test]
fn malformed_input_exits_1_with_file_and_line() {
    let cases: [(&[u8], usize); 8] = [
        (b"1 1 0 0 0 1 -1\n2 3 1 0\n", 2),
        (b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n", 2),
        (b"1 1 0 0 0 inf -1\n", 1),
        (b"1 1 0 0 0 1 -1\n1 3 1 0 0 1 1\n", 2),
        (b"1 1 0 0 0 1 -1\n2 3 1 0 0 1 5\n", 2),
        (b"1 1 0 0 0 1 -1\n2 3 1 0 0 1 3\n3 3 1 0 0 1 2\n", 2),
        (b"", 1),
        (b"\x00\x01\x02", 1),
    ];
    for (i, (content, line)) in cases.iter().enumerate() {
        let p = tmp(&format!("bad{i}.swc"));
        std::fs::write(&p, content).unwrap();
        let ps = p.to_str().unwrap();
        // --strict refuses the parent cycle (case 5) that is otherwise broken.
        for args in [
            vec!["info", ps, "--strict"],
            vec!["mesh", ps, "-o", "/dev/null/x.obj", "--strict"],
        ] {
            let out = neuromesh(&args);
            assert_eq!(out.status.code(), Some(1), "case {i}: {args:?}");
            let err = text(&out.stderr);
            let expect = format!("error: {ps}:{line}: ");
            assert!(
                err.starts_with(&expect),
                "case {i}: `{err}` should start with `{expect}`"
            );
            assert_eq!(err.lines().count(), 1, "one line: {err}");
        }
    }
}

#[test]
fn a_parent_cycle_is_broken_with_a_warning() {
    let p = tmp("cycle.swc");
    std::fs::write(
        &p,
        "1 1 0 0 0 2 -1\n2 3 3 0 0 1 1\n3 3 6 0 0 1 5\n4 3 9 0 0 1 3\n5 3 9 3 0 1 4\n",
    )
    .unwrap();
    let ps = p.to_str().unwrap();
    let o = tmp("cycle.ply");
    let out = neuromesh(&["mesh", ps, "-o", o.to_str().unwrap(), "--check"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains(&format!("warning: {ps}: 1 cycles of parent links broken")),
        "{err}"
    );
    assert!(text(&out.stdout).contains("1 cycles broken"));
    let info = text(&neuromesh(&["info", ps]).stdout);
    assert!(info.contains("1 parent cycles broken"), "{info}");
}

#[test]
fn missing_file_and_bad_output_extension() {
    let out = neuromesh(&["info", "no/such/file.swc"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).starts_with("error: no/such/file.swc: "));
    let out = neuromesh(&["mesh", "tests/data/y_bifurcation.swc", "-o", "out.xyz"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains(".obj, .ply or .stl"));
    let out = neuromesh(&[
        "mesh",
        "tests/data/y_bifurcation.swc",
        "-o",
        "x.obj",
        "--min-vertices",
        "5",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("min_vertices"));
}

#[test]
fn mesh_writes_each_format_and_check_reads_it_back() {
    for ext in ["obj", "ply", "stl"] {
        let p = tmp(&format!("y.{ext}"));
        let ps = p.to_str().unwrap();
        let out = neuromesh(&["mesh", "tests/data/y_bifurcation.swc", "-o", ps]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(Path::new(ps).metadata().unwrap().len() > 0);
        let out = neuromesh(&["check", ps, "--json"]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let s = text(&out.stdout);
        assert!(s.contains("\"closed\":true"), "{ext}: {s}");
    }
}

#[test]
fn a_cell_far_from_the_origin_is_written_exactly_and_stl_warns() {
    // The glial cell's 0.025-unit processes moved 10⁴ units away: written
    // with its absolute coordinates, valid when read back; STL is f32 only.
    let src = std::fs::read_to_string("tests/data/real/glia_type7_kannan_P1CS-31.CNG.swc")
        .expect("reads");
    let moved: String = src
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            if l.starts_with('#') || f.len() < 7 {
                return format!("{l}\n");
            }
            let c = |i: usize, d: f64| f[i].parse::<f64>().unwrap() + d;
            format!(
                "{} {} {} {} {} {} {}\n",
                f[0],
                f[1],
                c(2, 12345.678),
                c(3, -23456.789),
                c(4, 5432.1),
                f[5],
                f[6]
            )
        })
        .collect();
    let swc = tmp("far.swc");
    std::fs::write(&swc, moved).expect("writes");
    for ext in ["obj", "ply", "stl"] {
        let p = tmp(&format!("far.{ext}"));
        let ps = p.to_str().unwrap();
        let out = neuromesh(&["mesh", swc.to_str().unwrap(), "-o", ps]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let warned = text(&out.stderr).contains("STL stores f32 coordinates");
        assert_eq!(warned, ext == "stl", "{ext}: {}", text(&out.stderr));
        if ext == "obj" {
            let obj = std::fs::read_to_string(&p).expect("reads");
            let x: f64 = obj
                .lines()
                .find(|l| l.starts_with("v "))
                .expect("a vertex")
                .split_whitespace()
                .nth(1)
                .unwrap()
                .parse()
                .unwrap();
            assert!((x - 12345.678).abs() < 100.0, "absolute coordinates: {x}");
        }
        if ext != "stl" {
            let out = neuromesh(&["check", ps, "--json"]);
            assert!(out.status.success(), "{}", text(&out.stderr));
            let s = text(&out.stdout);
            assert!(s.contains("\"valid\":true"), "{ext}: {s}");
        }
    }
}

/// A box as OBJ text with optional faults, for `check`.
fn box_obj(drop_last: bool, flip: bool, overlap: bool) -> String {
    let mut v: Vec<[f32; 3]> = (0..8)
        .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
        .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    if drop_last {
        f.pop();
    }
    if flip {
        f[3].swap(1, 2);
    }
    if overlap {
        let n = v.len() as u32;
        let moved: Vec<[f32; 3]> = v.iter().map(|p| p.map(|c| c + 0.5)).collect();
        let shifted: Vec<[u32; 3]> = f.iter().map(|t| t.map(|k| k + n)).collect();
        v.extend(moved);
        f.extend(shifted);
    }
    let mut s = String::new();
    for p in &v {
        s.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    for t in &f {
        s.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    s
}

#[test]
fn check_reports_exactly_the_faults_of_a_box() {
    let run = |name: &str, obj: String| -> String {
        let p = tmp(name);
        std::fs::write(&p, obj).unwrap();
        let out = neuromesh(&["check", p.to_str().unwrap(), "--json"]);
        assert!(out.status.success());
        text(&out.stdout)
    };
    let ok = run("box.obj", box_obj(false, false, false));
    for key in [
        "\"closed\":true",
        "\"manifold\":true",
        "\"outward\":true",
        "\"self_intersections\":0",
        "\"valid\":true",
    ] {
        assert!(ok.contains(key), "{key} in {ok}");
    }
    let open = run("open.obj", box_obj(true, false, false));
    assert!(
        open.contains("\"closed\":false") && open.contains("\"boundary_edges\":3"),
        "{open}"
    );
    assert!(
        open.contains("\"misoriented_edges\":0") && open.contains("\"self_intersections\":0"),
        "{open}"
    );
    let flipped = run("flip.obj", box_obj(false, true, false));
    assert!(
        flipped.contains("\"closed\":true") && flipped.contains("\"misoriented_edges\":3"),
        "{flipped}"
    );
    assert!(flipped.contains("\"self_intersections\":0"), "{flipped}");
    let overlap = run("overlap.obj", box_obj(false, false, true));
    assert!(
        overlap.contains("\"closed\":true") && overlap.contains("\"components\":2"),
        "{overlap}"
    );
    assert!(!overlap.contains("\"self_intersections\":0"), "{overlap}");

    let p = tmp("strict.obj");
    std::fs::write(&p, box_obj(true, false, false)).unwrap();
    let out = neuromesh(&["check", p.to_str().unwrap(), "--strict"]);
    assert_eq!(out.status.code(), Some(3));
}

#[test]
fn help_lists_the_parameters() {
    let out = neuromesh(&["mesh", "--help"]);
    let s = text(&out.stdout);
    for name in neuromesh::PARAM_NAMES {
        assert!(
            s.contains(&format!("--{}", name.replace('_', "-"))),
            "{name} missing from\n{s}"
        );
    }
}

#[test]
fn batch_goes_past_a_bad_file_and_output_does_not_depend_on_threads() {
    let input = tmp("batch-in");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::copy("tests/data/y_bifurcation.swc", input.join("y.swc")).unwrap();
    std::fs::copy(
        "tests/data/real/rat_CA1_CCK_interneuron_cck7632.CNG.swc",
        input.join("cck.SWC"),
    )
    .unwrap();
    std::fs::write(input.join("bad.swc"), b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n").unwrap();
    std::fs::write(input.join("notes.txt"), b"not an swc file").unwrap();
    let mut outputs = Vec::new();
    for jobs in ["1", "2"] {
        let out_dir = tmp(&format!("batch-out-{jobs}"));
        let out = neuromesh(&[
            "batch",
            input.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "-j",
            jobs,
        ]);
        let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
        assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
        assert!(stderr.contains("bad.swc:2:"), "{stderr}");
        assert!(stdout.contains("3 (2 meshed, 1 failed)"), "{stdout}");
        // Piped: no progress bar.
        assert!(!stderr.contains('\r'), "{stderr:?}");
        let read = |name: &str| std::fs::read(out_dir.join(name)).expect(name);
        assert!(!out_dir.join("bad.ply").exists());
        assert!(!out_dir.join("notes.ply").exists());
        outputs.push((read("y.ply"), read("cck.ply")));
    }
    assert!(
        outputs[0] == outputs[1],
        "output depends on the thread count"
    );

    // A pattern, another format, and success.
    let out_dir = tmp("batch-out-obj");
    let pattern = input.join("zz*.swc");
    let out = neuromesh(&[
        "batch",
        input.join("y*").to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
        "--format",
        "obj",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(out_dir.join("y.obj").exists());
    assert!(text(&out.stdout).contains("1 (1 meshed, 0 failed)"));
    // Nothing matched is an error before any work.
    let out = neuromesh(&["batch", pattern.to_str().unwrap(), "-o", "x"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("matches no file"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn batch_keeps_dotted_names_and_meshes_past_a_name_collision() {
    let (a, b) = (tmp("batch-dots-a"), tmp("batch-dots-b"));
    for dir in [&a, &b] {
        std::fs::create_dir_all(dir).unwrap();
    }
    for name in [
        "H17.03.013.11.08.04.swc",
        "H17.03.013.11.08.05.swc",
        "y.swc",
    ] {
        std::fs::copy("tests/data/y_bifurcation.swc", a.join(name)).unwrap();
    }
    std::fs::copy("tests/data/y_bifurcation.swc", b.join("y.SWC")).unwrap();
    let out_dir = tmp("batch-dots-out");
    let out = neuromesh(&[
        "batch",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("4 (3 meshed, 1 failed)"), "{stdout}");
    assert!(
        stderr.contains("y.SWC is not meshed") && stderr.contains("already that of"),
        "{stderr}"
    );
    for name in [
        "H17.03.013.11.08.04.ply",
        "H17.03.013.11.08.05.ply",
        "y.ply",
    ] {
        assert!(out_dir.join(name).exists(), "{name}");
    }
}

#[test]
fn gzip_files_and_standard_input_are_read() {
    use std::io::Write;
    let swc = std::fs::read("tests/data/y_bifurcation.swc").unwrap();
    let dir = tmp("gz-in");
    std::fs::create_dir_all(&dir).unwrap();
    let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(&swc).unwrap();
    std::fs::write(dir.join("cell.swc.gz"), z.finish().unwrap()).unwrap();
    // A folder gives its .swc.gz files; the output drops the whole suffix.
    let out_dir = tmp("gz-out");
    let out = neuromesh(&[
        "batch",
        dir.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let from_gz = std::fs::read(out_dir.join("cell.ply")).unwrap();
    let plain = tmp("gz-plain.ply");
    let out = neuromesh(&[
        "mesh",
        "tests/data/y_bifurcation.swc",
        "-o",
        plain.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert_eq!(from_gz, std::fs::read(&plain).unwrap());
    // `-` reads standard input; its errors say <stdin>.
    let run_stdin = |args: &[&str], input: &[u8]| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_neuromesh"))
            .args(args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("the binary runs");
        child.stdin.take().unwrap().write_all(input).unwrap();
        child.wait_with_output().unwrap()
    };
    let piped = tmp("gz-stdin.ply");
    let out = run_stdin(&["mesh", "-", "-o", piped.to_str().unwrap()], &swc);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        std::fs::read(&piped).unwrap(),
        std::fs::read(&plain).unwrap()
    );
    // `-o -` writes the mesh to standard output (what is said goes to stderr).
    let out = run_stdin(
        &["mesh", "-", "-o", "-", "--format", "ply", "--check"],
        &swc,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(out.stdout, std::fs::read(&plain).unwrap());
    assert!(
        text(&out.stderr).contains("valid "),
        "{}",
        text(&out.stderr)
    );
    let out = neuromesh(&["mesh", "tests/data/y_bifurcation.swc", "-o", "-"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("needs --format"),
        "{}",
        text(&out.stderr)
    );
    let out = neuromesh(&[
        "mesh",
        "tests/data/y_bifurcation.swc",
        "-o",
        plain.to_str().unwrap(),
        "--format",
        "obj",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("disagrees"),
        "{}",
        text(&out.stderr)
    );
    let out = run_stdin(&["info", "-"], b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).starts_with("error: <stdin>:2: "),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn batch_resumes_and_writes_its_summary() {
    let input = tmp("batch-resume-in");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::copy("tests/data/y_bifurcation.swc", input.join("y.swc")).unwrap();
    std::fs::write(input.join("bad.swc"), b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n").unwrap();
    let (out_dir, csv) = (tmp("batch-resume-out"), tmp("batch-resume.csv"));
    let run = || {
        neuromesh(&[
            "batch",
            input.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "--skip-existing",
            "--summary",
            csv.to_str().unwrap(),
        ])
    };
    let first = run();
    assert_eq!(first.status.code(), Some(1), "{}", text(&first.stderr));
    let table = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines[0], "input,output,status,triangles,seconds,message");
    assert!(
        lines[1].contains("bad.swc") && lines[1].contains(",failed,"),
        "{table}"
    );
    assert!(
        lines[2].contains("y.swc") && lines[2].contains(",meshed,1"),
        "{table}"
    );
    // Again: the mesh that exists is left alone, the bad file fails again.
    let again = run();
    assert!(
        text(&again.stdout).contains("(0 meshed, 1 failed, 1 skipped)"),
        "{}",
        text(&again.stdout)
    );
    let table = std::fs::read_to_string(&csv).unwrap();
    assert!(table.contains(",skipped,"), "{table}");
}

#[test]
fn an_interrupted_batch_leaves_no_partial_file_and_says_what_it_did() {
    let input = tmp("batch-int-in");
    std::fs::create_dir_all(&input).unwrap();
    for name in [
        "rat_neocortex_interneuron_MTC260800D-IDA.CNG.swc",
        "mouse_allen_test_swc_26k.swc",
        "rat_L6B_pyramidal_BC-2009-10-12-D.CNG.swc",
    ] {
        std::fs::copy(format!("tests/data/real/{name}"), input.join(name)).unwrap();
    }
    let (out_dir, csv) = (tmp("batch-int-out"), tmp("batch-int.csv"));
    let child = Command::new(env!("CARGO_BIN_EXE_neuromesh"))
        .args([
            "batch",
            input.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "-j",
            "1",
            "--summary",
            csv.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("not done: interrupted"),
        "{}",
        text(&out.stdout)
    );
    let leftovers: Vec<_> = std::fs::read_dir(&out_dir)
        .map(|d| d.filter_map(Result::ok).map(|e| e.file_name()).collect())
        .unwrap_or_default();
    assert!(
        leftovers
            .iter()
            .all(|n| !n.to_string_lossy().ends_with(".tmp")),
        "{leftovers:?}"
    );
    assert!(csv.exists(), "no summary written on interrupt");
}
