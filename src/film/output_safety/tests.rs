use super::*;
use crate::film::image_io::{write_exr, Image};
use crate::math::color::Rgb;

fn image(spp: u32, partial: bool) -> Image {
    Image {
        width: 2,
        height: 1,
        pixels: vec![Rgb::new(0.25, 0.5, 1.0); 2],
        spp,
        partial,
    }
}

fn message(plan: &Plan) -> String {
    plan.check().unwrap_err().to_string()
}

#[test]
fn every_spelling_of_a_file_has_one_identity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::write(d.join("a.exr"), b"a").unwrap();
    std::fs::write(d.join("b.exr"), b"b").unwrap();
    std::os::unix::fs::symlink("a.exr", d.join("link.exr")).unwrap();
    std::os::unix::fs::symlink(d.join("sub"), d.join("sublink")).unwrap();
    std::fs::hard_link(d.join("a.exr"), d.join("hard.exr")).unwrap();
    let a = identity(&d.join("a.exr"));
    for same in [
        "link.exr",
        "hard.exr",
        "sub/../a.exr",
        "./a.exr",
        "sublink/../a.exr",
    ] {
        assert_eq!(identity(&d.join(same)), a, "{same}");
    }
    assert_ne!(identity(&d.join("b.exr")), a);
    // Files still to be written: the same path however it is spelled.
    let new = identity(&d.join("sub/new.exr"));
    assert_eq!(identity(&d.join("sublink/new.exr")), new);
    assert_eq!(identity(&d.join("./sub/../sub/new.exr")), new);
    assert_ne!(identity(&d.join("sub/other.exr")), new);
    // A dangling link is the file it would create.
    std::os::unix::fs::symlink("sub/new.exr", d.join("dangling.exr")).unwrap();
    assert_eq!(identity(&d.join("dangling.exr")), new);
}

#[test]
fn an_output_that_is_an_input_is_refused_naming_flag_and_both_paths() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("piece.exr"), b"piece").unwrap();
    std::fs::hard_link(d.join("piece.exr"), d.join("alias.exr")).unwrap();
    let mut plan = Plan::new("merge");
    plan.input("piece", &d.join("piece.exr"));
    plan.output("-o", &d.join("alias.exr"), None);
    let e = message(&plan);
    assert!(e.starts_with("invalid argument -o: "), "{e}");
    assert!(
        e.contains("alias.exr is an input of the merge (piece: ") && e.contains("piece.exr)"),
        "{e}"
    );
    let mut fine = Plan::new("merge");
    fine.input("piece", &d.join("piece.exr"));
    fine.output("-o", &d.join("merged.exr"), None);
    fine.check().unwrap();
}

#[test]
fn two_outputs_on_one_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::os::unix::fs::symlink("x.exr", d.join("y.png")).unwrap();
    let mut plan = Plan::new("render");
    plan.image_output("--out", &d.join("x.exr"), Some("frame 2"));
    plan.image_output("--png", &d.join("y.png"), Some("frame 2"));
    let e = message(&plan);
    assert!(
        e.starts_with("invalid argument --png: ")
            && e.contains("y.png (frame 2) is the same file as --out ")
            && e.contains("x.exr (frame 2)"),
        "{e}"
    );
    // The file a partial image may go to counts as an output too.
    let mut plan = Plan::new("render");
    plan.image_output("--out", &d.join("r.exr"), None);
    plan.output("--png", &d.join("r.partial.exr"), None);
    assert!(message(&plan).contains("r.partial.exr (where a partial image goes beside "));
}

#[test]
fn an_output_inside_an_input_sequence_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut plan = Plan::new("render");
    plan.input_sequence("medium[0].file", &d.join("vol.####.vdb"));
    plan.output("--out", &d.join("vol.7.vdb"), Some("frame 7"));
    let e = message(&plan);
    assert!(
        e.contains("vol.7.vdb (frame 7) would be a frame of the sequence")
            && e.contains("vol.####.vdb that medium[0].file reads"),
        "{e}"
    );
    for fine in ["vol.7.exr", "vol.x7.vdb", "vol..vdb", "avol.0007.vdb"] {
        let mut plan = Plan::new("render");
        plan.input_sequence("medium[0].file", &d.join("vol.####.vdb"));
        plan.output("--out", &d.join(fine), None);
        plan.check().unwrap_or_else(|e| panic!("{fine}: {e}"));
    }
    assert!(frame_of(Path::new("v.####.vdb"), "v.-0003.vdb"));
}

#[test]
fn unwritable_outputs_name_the_flag_and_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("dir")).unwrap();
    for (path, needle) in [
        (d.join("dir"), "is a directory"),
        (d.join("missing/x.exr"), "does not exist"),
        (PathBuf::from("/dev/null"), "not a regular file"),
    ] {
        let mut plan = Plan::new("render");
        plan.output("--out", &path, None);
        let e = message(&plan);
        assert!(
            e.starts_with("invalid argument --out: ")
                && e.contains(&path.display().to_string())
                && e.contains(needle),
            "{e}"
        );
    }
}

#[test]
fn partial_paths_sit_beside_the_output() {
    assert_eq!(
        partial_path(Path::new("out/render.exr")),
        Path::new("out/render.partial.exr")
    );
    assert_eq!(
        partial_path(Path::new("seq.0003.png")),
        Path::new("seq.0003.partial.png")
    );
    assert_eq!(partial_path(Path::new("out")), Path::new("out.partial"));
}

#[test]
fn a_partial_image_replaces_only_nothing_or_a_lesser_partial() {
    let dir = tempfile::tempdir().unwrap();
    let (exr, png) = (dir.path().join("r.exr"), dir.path().join("r.png"));
    let (beside_exr, beside_png) = (partial_path(&exr), partial_path(&png));
    let here = |p: &Placement| (p.exr.clone(), p.png.clone());
    // Nothing there: the requested files.
    let p = place_partial(&exr, Some(&png), 8);
    assert_eq!(here(&p), (Some(exr.clone()), Some(png.clone())));
    assert!(p.note().is_none());
    // A partial of at most as many samples is replaced.
    write_exr(&exr, &image(8, true)).unwrap();
    assert_eq!(place_partial(&exr, Some(&png), 8).exr, Some(exr.clone()));
    // More samples, a complete image or a file brume did not write: beside it, PNG too.
    for (existing, what) in [
        (Some(image(9, true)), "a partial image of 9 spp"),
        (Some(image(2, false)), "a complete image of 2 spp"),
        (None, "a file brume did not write"),
    ] {
        match existing {
            Some(im) => write_exr(&exr, &im).unwrap(),
            None => std::fs::write(&exr, b"someone else's file").unwrap(),
        }
        let p = place_partial(&exr, Some(&png), 8);
        assert_eq!(
            here(&p),
            (Some(beside_exr.clone()), Some(beside_png.clone())),
            "{what}"
        );
        let note = p.note().unwrap();
        assert!(note.contains(what) && note.contains("kept"), "{note}");
    }
    // Beside it the same rule: when both hold better images, nothing is written.
    write_exr(&beside_exr, &image(64, true)).unwrap();
    let p = place_partial(&exr, Some(&png), 8);
    assert_eq!(here(&p), (None, None));
    assert!(p.note().unwrap().contains("not saved"), "{:?}", p.note());
    write_exr(&beside_exr, &image(4, true)).unwrap();
    assert_eq!(place_partial(&exr, None, 8).exr, Some(beside_exr));
}

#[test]
fn every_file_of_an_input_sequence_is_an_input_whatever_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("v.0002.vdb"), b"frame 2").unwrap();
    std::fs::hard_link(d.join("v.0002.vdb"), d.join("alias.exr")).unwrap();
    let mut plan = Plan::new("render");
    plan.input_sequence("medium[0].file", &d.join("v.####.vdb"));
    plan.image_output_frames("--out", &d.join("alias.exr"), &[1]);
    let e = message(&plan);
    assert!(
        e.contains("alias.exr (frame 1) is an input of the render (medium[0].file: ")
            && e.contains("v.0002.vdb)"),
        "{e}"
    );
    // Frames of one pattern that a link makes one file.
    std::os::unix::fs::symlink("o.0002.exr", d.join("o.0001.exr")).unwrap();
    let mut plan = Plan::new("render");
    plan.image_output_frames("--out", &d.join("o.####.exr"), &[1, 2, 3]);
    let e = message(&plan);
    assert!(
        e.contains("o.0002.exr (frame 2) is the same file as --out ")
            && e.contains("o.0001.exr (frame 1)"),
        "{e}"
    );
}
