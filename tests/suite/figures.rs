//! The report's pictures and page: Fig. 8 statistics on images with known differences,
//! Newton's CSV against `colour::newton_sequence`, plots of the right size, a self-contained
//! index.html naming every case, and the figure scenes themselves.

use fringe::colour::{self, Adaptation, Illuminant, WavelengthGrid};
use fringe::harness::check::{self, CheckOptions, Format};
use fringe::output::figures::{self, FigureOptions};
use fringe::output::report::image::{self as img, Rgb8Image};
use fringe::output::report::{html, plot};
use std::path::{Path, PathBuf};

fn grey(width: usize, height: usize, v: u8) -> Rgb8Image {
    Rgb8Image {
        width,
        height,
        pixels: vec![[v; 3]; width * height],
    }
}

#[test]
fn fig8_statistics_of_known_differences() {
    let a = grey(5, 4, 100);
    let mut b = a.clone();
    // Three differing pixels (column, row): (1, 0) by (+3, 0, -2) → sum 5, max 3;
    // (4, 2) by (0, 7, 0) → sum 7, max 7; (0, 3) by (-2, -2, -3) → sum 7 (tie: earlier wins), max 3.
    b.pixels[1] = [103, 100, 98];
    b.pixels[2 * 5 + 4] = [100, 107, 100];
    b.pixels[3 * 5] = [98, 98, 97];
    let s = img::diff_stats(&a, &b).unwrap();
    assert_eq!(s.pixels, 20);
    assert_eq!(s.differing, 3);
    assert_eq!((s.max_sum, s.max_sum_at), (7, (4, 2)));
    assert_eq!((s.max_channel, s.max_channel_at), (7, (4, 2)));
    // Symmetric in its arguments.
    assert_eq!(img::diff_stats(&b, &a).unwrap(), s);
    // Histogram stretch: the largest channel difference becomes 255, zero stays zero.
    let (d, factor) = img::stretched_difference(&a, &b).unwrap();
    assert!((factor - 255.0 / 7.0).abs() < 1e-12);
    assert_eq!(d.at(4, 2), [0, 255, 0]);
    assert_eq!(
        d.at(1, 0),
        [
            (3.0 * factor).round() as u8,
            0,
            (2.0 * factor).round() as u8
        ]
    );
    assert_eq!(d.at(2, 2), [0, 0, 0]);
    // Identical pictures: nothing differs, the stretch leaves black.
    let s0 = img::diff_stats(&a, &a).unwrap();
    assert_eq!((s0.differing, s0.max_sum, s0.max_channel), (0, 0, 0));
    // Different sizes are an error.
    assert!(img::diff_stats(&a, &grey(4, 5, 0)).is_err());
}

#[test]
fn png_round_trip_and_base64() {
    let mut p = grey(3, 2, 7);
    p.pixels[4] = [1, 2, 250];
    let bytes = p.png().unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(img::decode_png(&bytes).unwrap(), p);
    // RFC 4648 test vectors.
    for (raw, enc) in [
        ("", ""),
        ("f", "Zg=="),
        ("fo", "Zm8="),
        ("foo", "Zm9v"),
        ("foob", "Zm9vYg=="),
        ("fooba", "Zm9vYmE="),
        ("foobar", "Zm9vYmFy"),
    ] {
        assert_eq!(html::base64(raw.as_bytes()), enc);
    }
    assert_eq!(
        html::escape("<a href=\"x\">&'"),
        "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
    );
}

#[test]
fn monochrome_pictures_are_full_scale_in_the_hue_of_their_wavelength() {
    // Intensities 0, ¼, 1 at 650 nm: the brightest pixel is the full hue (its largest channel
    // 255), zero is black, and ¼ is a quarter of the linear hue.
    let hue = colour::wavelength_to_srgb_hue(650e-9);
    let pic = img::monochrome(3, 1, &[0.0, 0.5, 2.0], 650e-9, 2.0);
    assert_eq!(pic.at(0, 0), [0, 0, 0]);
    assert_eq!(pic.at(2, 0), colour::to_srgb8(hue));
    assert_eq!(*pic.at(2, 0).iter().max().unwrap(), 255);
    assert_eq!(pic.at(1, 0), colour::to_srgb8(hue.map(|h| 0.25 * h)));
}

#[test]
fn newton_csv_rows_agree_with_the_sequence() {
    let thick = figures::newton_thicknesses_m(1);
    assert_eq!(thick.len(), 1501);
    assert_eq!(thick[1500], 1500e-9);
    let grid = WavelengthGrid::cie_1nm();
    for (ill, adapt) in [
        (Illuminant::D65, Adaptation::None),
        (Illuminant::E, Adaptation::Bradford),
    ] {
        let csv = colour::write_newton_csv(figures::NEWTON_N, &thick, &grid, ill, adapt).unwrap();
        let rows = colour::newton_sequence(figures::NEWTON_N, &thick, &grid, ill, adapt).unwrap();
        let lines: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(lines[0], "thickness_nm,X,Y,Z,R_lin,G_lin,B_lin,R8,G8,B8");
        assert_eq!(lines.len(), 1 + 1501);
        for (k, line) in lines[1..].iter().enumerate() {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), 10);
            assert_eq!(
                f[0].parse::<f64>().unwrap(),
                k as f64,
                "thickness of row {k}"
            );
            for c in 0..3 {
                let x: f64 = f[1 + c].parse().unwrap();
                assert!((x - rows[k].xyz[c]).abs() <= 1e-9 * rows[k].xyz[c].abs().max(1e-12));
                assert_eq!(f[7 + c].parse::<u8>().unwrap(), rows[k].srgb8[c]);
            }
        }
        // Zero thickness reflects nothing: black.
        assert_eq!(rows[0].srgb8, [0, 0, 0]);
    }
}

#[test]
fn figure_scenes_load_and_validate_grids() {
    for f in [
        "figures/plate_amplitude_division.json",
        "figures/young_fig3.json",
    ] {
        let c = fringe::harness::case::load::load(Path::new(f)).unwrap();
        assert!(
            matches!(
                c.spec.probe,
                fringe::harness::case::spec::Probe::Grid { .. }
            ),
            "{f}"
        );
    }
    assert_eq!(
        std::fs::read_to_string("figures/plate_amplitude_division.json").unwrap(),
        figures::PLATE_SCENE
    );
    let text = figures::PLATE_SCENE;
    for (bad, path) in [
        (
            text.replace(
                "\"v_axis\": [\n        0,\n        1,\n        0\n      ]",
                "\"v_axis\": [2, 0, 0]",
            ),
            "$.probe.grid.v_axis",
        ),
        (
            text.replace(
                "\"pixels\": [\n        60,\n        60\n      ]",
                "\"pixels\": [0, 60]",
            ),
            "$.probe.grid.pixels",
        ),
        (
            text.replace(
                "\"size_m\": [\n        0.06,\n        0.06\n      ]",
                "\"size_m\": [0.06, -1]",
            ),
            "$.probe.grid.size_m[1]",
        ),
    ] {
        assert_ne!(bad, text, "the replacement for {path} did not apply");
        let e = fringe::harness::case::load::parse(Path::new("bad.json"), &bad).unwrap_err();
        assert_eq!(e.json_path, path, "{e}");
    }
}

/// A small check run (three quick cases) plus a tiny figure set into a temporary folder.
fn small_report() -> (tempfile::TempDir, PathBuf, check::CheckOutcome) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("reports");
    let opts = CheckOptions {
        cases: vec![
            "young_paper".into(),
            "plate_airy_s".into(),
            "lloyd_mirror".into(),
        ],
        cases_dir: "cases".into(),
        golden_dir: None,
        out: out.clone(),
        format: Format::Table,
        bless: false,
    };
    let outcome = fringe::cli::check(&opts).unwrap_or_else(|e| panic!("{}", e.0));
    (dir, out, outcome)
}

#[test]
fn report_plots_pictures_and_a_self_contained_page() {
    let (_dir, out, outcome) = small_report();
    for r in &outcome.results {
        let size = plot::profile_size(r).expect("every case here has a profile");
        let png = img::decode_png(&std::fs::read(out.join(&r.name).join("profile.png")).unwrap())
            .unwrap();
        assert_eq!((png.width as u32, png.height as u32), size, "{}", r.name);
        // Plots are not blank: some pixels are neither white nor grey.
        assert!(
            png.pixels.iter().any(|p| p[0] != p[1] || p[1] != p[2]),
            "{}",
            r.name
        );
    }
    let conv =
        img::decode_png(&std::fs::read(out.join("plate_airy_s/convergence.png")).unwrap()).unwrap();
    assert_eq!(
        (conv.width as u32, conv.height as u32),
        plot::CONVERGENCE_SIZE
    );
    let strip =
        img::decode_png(&std::fs::read(out.join("young_paper/picture.png")).unwrap()).unwrap();
    assert_eq!((strip.width, strip.height), (401, html::STRIP_HEIGHT));

    // The figures, tiny, then the page again.
    let m = figures::generate(
        &out,
        &FigureOptions {
            size: (12, 10),
            samples: 4,
            illuminant: Illuminant::D65,
            error_size: 5,
            progress: false,
        },
    )
    .unwrap();
    assert_eq!(m.fig8.len(), 3);
    for e in &m.fig8 {
        assert_eq!(e.stats.pixels, 120);
    }
    // vector vs paper_rules: identical pictures (no total internal reflection in the scene).
    let v = m.fig8.iter().find(|e| e.left == "vector").unwrap();
    assert_eq!(v.stats.differing, 0);
    assert_eq!(
        m.colour_error.iter().map(|r| r.samples).collect::<Vec<_>>(),
        figures::ERROR_SAMPLES
    );
    html::write_index(&out).unwrap();
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        !page.contains("http://") && !page.contains("https://"),
        "the page references the network"
    );
    assert!(
        !page.contains("src=\"figures/") && !page.contains("src=\"young"),
        "images must be embedded"
    );
    for r in &outcome.results {
        assert!(
            page.contains(&format!("id=\"case-{}\"", r.name)),
            "{} missing",
            r.name
        );
        assert!(
            page.contains(&html::escape(&r.description)),
            "{} description missing",
            r.name
        );
    }
    for f in &m.figures {
        assert!(
            page.contains(&html::escape(&f.title)),
            "{} missing",
            f.title
        );
    }
    assert!(page.contains("class=\"pass\""));
    assert!(page.matches("data:image/png;base64,").count() >= 3 * 2 + m.figures.len() + 3);
    assert!(
        page.contains("79041"),
        "the paper's Fig. 8 numbers are shown"
    );
}

#[test]
fn colour_error_falls_with_spectral_samples() {
    let rows = figures::colour_error_study(&FigureOptions {
        size: (4, 4),
        samples: 4,
        illuminant: Illuminant::D65,
        error_size: 6,
        progress: false,
    })
    .unwrap();
    let first = &rows[0];
    let last = rows.last().unwrap();
    assert_eq!((first.samples, last.samples), (4, 401));
    // 401 samples over 380–780 nm are the 1 nm reference without its tails below 380 and above
    // 780 nm, where the CMFs are < 1e-3 of their peak: far below a just-noticeable difference.
    assert!(last.newton_d65_max < 0.5, "{last:?}");
    assert!(last.plate_max < 0.5, "{last:?}");
    // 4 samples cannot reproduce Newton's colours.
    assert!(first.newton_d65_mean > 5.0, "{first:?}");
    assert!(first.newton_d65_mean > 10.0 * last.newton_d65_mean);
}
