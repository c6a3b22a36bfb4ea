//! The deck contract (docs/spec/deck.md): every statement, the
//! syntax details, every error class with its line:column, and the writer's
//! round trip.

use frfup_parsers::deck::{
    format_number, parse, write, Analysis, DampingModel, DeckDof, FixDofs, Pos, Quantity, Theory,
};

const FULL: &str = "\
# a full deck
title GARTEUR-like  test  bed   # trailing comment
analysis space
material alu E=7.2e10 rho=2.7D+03 nu=0.3
material steel\trho=7850 E=2.1E+11 G=8.1e10
section wing A=1e-3 Iy=8.3e-10 Iz=8.3e-8 J=3.2e-9 ky=0.85
section fus Iy=1.5e-6 A=7.5e-3 Iz=1.4e-5 J=4e-6 kz=0.6

node 1 0 0 0
node 2 1.0 0 0
node 3 1 1 0.5
beam 1 1 2 alu wing
beam 2 2 3 steel fus orient=0,0,1 theory=timoshenko
beam 3 3 1 alu fus theory=eb
mass 1 3 m=0.2 Ixx=1e-4 Izz=2e-4
spring 1 1 z k=4000
spring 2 2 rx k=10 to=3
fix 1 x,y,rz
fix 2 all
damping rayleigh 0.1 1e-5
param Ewing E 1
param I Iy 1-3
param tip m 1
param bungee k 1-2
sensor 112 3
";

#[test]
fn parses_every_statement() {
    let d = parse(FULL).unwrap();
    assert_eq!(d.title(), "GARTEUR-like  test  bed");
    assert_eq!(d.analysis, Analysis::Space);
    assert_eq!(d.analysis_pos, Some(Pos::new(3, 1)));
    let alu = d.material("alu").unwrap();
    assert_eq!(
        (alu.e, alu.rho, alu.nu, alu.g),
        (7.2e10, 2700.0, Some(0.3), None)
    );
    assert!((alu.shear_modulus() - 7.2e10 / 2.6).abs() < 1.0);
    let st = d.material("steel").unwrap();
    assert_eq!((st.e, st.g), (2.1e11, Some(8.1e10)));
    let fus = d.section("fus").unwrap();
    assert_eq!(
        (fus.a, fus.iy, fus.ky(), fus.kz()),
        (7.5e-3, 1.5e-6, 5.0 / 6.0, 0.6)
    );
    assert_eq!(d.nodes[2].xyz, [1.0, 1.0, 0.5]);
    assert_eq!(d.nodes[2].pos, Pos::new(11, 1));
    let b2 = d.beam(2).unwrap();
    assert_eq!(b2.nodes, [2, 3]);
    assert_eq!(b2.orient.unwrap().vector, [0.0, 0.0, 1.0]);
    assert_eq!(b2.orient.unwrap().pos, Pos::new(13, 29));
    assert_eq!(b2.theory(), Theory::Timoshenko);
    assert_eq!(d.beam(1).unwrap().theory, None);
    assert_eq!(d.masses[0].ixx, Some(1e-4));
    assert_eq!(d.masses[0].iyy, None);
    assert_eq!(d.springs[1].dof, DeckDof::Rx);
    assert_eq!(d.springs[1].to, Some(3));
    assert_eq!(
        d.fixes[0].dofs,
        FixDofs::List(vec![DeckDof::X, DeckDof::Y, DeckDof::Rz])
    );
    assert_eq!(d.fixes[1].dofs, FixDofs::All);
    assert_eq!(
        d.damping.unwrap().model,
        DampingModel::Rayleigh {
            alpha: 0.1,
            beta: 1e-5
        }
    );
    let p = d.param("I").unwrap();
    assert_eq!(p.quantity, Quantity::Iy);
    assert_eq!(p.ids().collect::<Vec<_>>(), vec![1, 2, 3]);
    assert_eq!(d.sensors[0].test_node, 112);
}

#[test]
fn defaults_and_ranges() {
    let d = parse("node 1 0 0 0\nnode 2 1 0 0\nmaterial m E=1 rho=1\nsection s A=1 Iy=1 Iz=1 J=1\nbeam 1 1 2 m s\nbeam 2 1 2 m s\nbeam 3 2 1 m s\nbeam 7 2 1 m s\nparam p E 1-3,7\n").unwrap();
    assert_eq!(d.analysis, Analysis::Space);
    assert_eq!(d.analysis_pos, None);
    assert_eq!(d.damping, None);
    assert_eq!(d.params[0].ids().collect::<Vec<_>>(), vec![1, 2, 3, 7]);
    assert_eq!(d.params[0].ids[1].pos, Pos::new(9, 15));
}

/// `(deck, line, column, part of the message)`.
fn err(text: &str) -> (u32, u32, String) {
    let e = parse(text).expect_err(text);
    (e.line, e.column, e.message)
}

fn assert_err(text: &str, line: u32, column: u32, needle: &str) {
    let (l, c, m) = err(text);
    assert_eq!((l, c), (line, column), "{m}\n--\n{text}");
    assert!(m.contains(needle), "`{m}` lacks `{needle}`");
}

const BASE: &str = "\
material m E=2e11 rho=7800
section s A=1e-3 Iy=1e-7 Iz=2e-7 J=1e-7
node 1 0 0 0
node 2 1 0 0
beam 1 1 2 m s
mass 1 2 m=1
spring 1 2 z k=100
";

#[test]
fn syntax_errors() {
    assert_err(
        "node 1 0 0 0\n  bem 1 1 2 m s\n",
        2,
        3,
        "unknown keyword `bem`",
    );
    assert_err("Node 1 0 0 0\n", 1, 1, "unknown keyword");
    assert_err("node 1 0 0\n", 1, 11, "missing Z");
    assert_err("node 1 0 0 0 9\n", 1, 14, "unexpected `9`");
    assert_err("node 1 0 x 0\n", 1, 10, "expected a number for Y");
    assert_err("node 0 0 0 0\n", 1, 6, "positive integer");
    assert_err("node -3 0 0 0\n", 1, 6, "positive integer");
    assert_err("node 1 1e 0 0\n", 1, 8, "expected a number");
    assert_err("material m E=2e11\n", 1, 18, "requires `rho=");
    assert_err(
        "material m E=2e11 rho=1 rho=2\n",
        1,
        25,
        "duplicate key `rho`",
    );
    assert_err(
        "material m E=2e11 rho=1 Nu=0.3\n",
        1,
        25,
        "unknown key `Nu`",
    );
    assert_err(
        "material m E=2e1x1 rho=1\n",
        1,
        14,
        "expected a number for E",
    );
    assert_err("section s A=1 Iy=1 17\n", 1, 20, "expected key=value");
    assert_err(
        &format!("{BASE}beam 2 1 2 m s orient=1,0\n"),
        8,
        23,
        "three numbers",
    );
    assert_err(
        &format!("{BASE}beam 2 1 2 m s orient=1,q,0\n"),
        8,
        25,
        "orient component",
    );
    assert_err(
        &format!("{BASE}beam 2 1 2 m s theory=euler\n"),
        8,
        23,
        "`eb` or `timoshenko`",
    );
    assert_err(&format!("{BASE}beam 2 1 2 m\n"), 8, 13, "missing SECTION");
    assert_err(
        &format!("{BASE}spring 2 1 w k=1\n"),
        8,
        12,
        "bad DOF name `w`",
    );
    assert_err(&format!("{BASE}fix 1 x,zz\n"), 8, 9, "bad DOF name `zz`");
    assert_err(&format!("{BASE}fix 1\n"), 8, 6, "missing DOFS");
    assert_err(
        "analysis plane\nanalysis space\n",
        2,
        1,
        "duplicate `analysis`",
    );
    assert_err("analysis 3d\n", 1, 10, "`plane` or `space`");
    assert_err("damping viscous 0.1\n", 1, 9, "unknown damping model");
    assert_err(
        "damping modal 0.01\ndamping modal 0.02\n",
        2,
        1,
        "duplicate `damping`",
    );
    assert_err("damping rayleigh 0.1\n", 1, 21, "missing BETA");
    assert_err(&format!("{BASE}param p E 1-\n"), 8, 11, "ID list");
    assert_err(&format!("{BASE}param p E 3-1\n"), 8, 11, "empty ID range");
    assert_err(
        &format!("{BASE}param p Ix 1\n"),
        8,
        9,
        "unknown quantity `Ix`",
    );
}

#[test]
fn semantic_errors() {
    duplicate_ids_and_names();
    undefined_references();
    non_positive_properties();
    parameters_on_missing_ids_or_quantities();
    analysis_restrictions();
}

fn duplicate_ids_and_names() {
    assert_err(
        &format!("{BASE}node 2 0 1 0\n"),
        8,
        6,
        "duplicate node ID 2",
    );
    assert_err(
        &format!("{BASE}beam 1 2 1 m s\n"),
        8,
        6,
        "duplicate beam ID 1",
    );
    assert_err(
        &format!("{BASE}mass 1 1 m=2\n"),
        8,
        6,
        "duplicate mass ID 1",
    );
    assert_err(
        &format!("{BASE}spring 1 1 x k=2\n"),
        8,
        8,
        "duplicate spring ID 1",
    );
    assert_err(
        &format!("{BASE}material m E=1 rho=1\n"),
        8,
        10,
        "duplicate material `m`",
    );
    assert_err(
        &format!("{BASE}section s A=1 Iy=1 Iz=1 J=1\n"),
        8,
        9,
        "duplicate section `s`",
    );
    assert_err(
        &format!("{BASE}param p E 1\nparam p A 1\n"),
        9,
        7,
        "duplicate parameter `p`",
    );
    assert_err(
        &format!("{BASE}sensor 5 1\nsensor 5 2\n"),
        9,
        8,
        "duplicate sensor",
    );
}

fn undefined_references() {
    assert_err(
        &format!("{BASE}beam 2 1 9 m s\n"),
        8,
        10,
        "undefined node 9",
    );
    assert_err(
        &format!("{BASE}beam 2 1 2 alu s\n"),
        8,
        12,
        "undefined material `alu`",
    );
    assert_err(
        &format!("{BASE}beam 2 1 2 m tube\n"),
        8,
        14,
        "undefined section `tube`",
    );
    assert_err(&format!("{BASE}beam 2 1 1 m s\n"), 8, 10, "to itself");
    assert_err(&format!("{BASE}mass 2 8 m=1\n"), 8, 8, "undefined node 8");
    assert_err(
        &format!("{BASE}spring 2 1 x k=1 to=8\n"),
        8,
        21,
        "undefined node 8",
    );
    assert_err(&format!("{BASE}fix 9 all\n"), 8, 5, "undefined node 9");
    assert_err(&format!("{BASE}sensor 100 9\n"), 8, 12, "undefined node 9");
    // A forward reference is fine; the error is the earliest in the file.
    assert!(parse("beam 1 1 2 m s\nnode 1 0 0 0\nnode 2 1 0 0\nmaterial m E=1 rho=1\nsection s A=1 Iy=1 Iz=1 J=1\n").is_ok());
    assert_err(
        "beam 1 1 2 m s\nnode 1 0 0 0\nnode 1 1 0 0\n",
        1,
        10,
        "undefined node 2",
    );
}

fn non_positive_properties() {
    assert_err("material m E=0 rho=1\n", 1, 14, "must be positive");
    assert_err("material m E=1 rho=-1\n", 1, 20, "must be positive");
    assert_err("material m E=1 rho=1 G=0\n", 1, 24, "must be positive");
    assert_err("material m E=1 rho=1 nu=-1\n", 1, 25, "must exceed -1");
    assert_err("section s A=1 Iy=0 Iz=1 J=1\n", 1, 18, "must be positive");
    assert_err(
        "section s A=1 Iy=1 Iz=1 J=-1e-9\n",
        1,
        27,
        "must be positive",
    );
    assert_err(
        "section s A=1 Iy=1 Iz=1 J=1 ky=0\n",
        1,
        32,
        "must be positive",
    );
    assert_err(
        &format!("{BASE}mass 2 1 m=-1\n"),
        8,
        12,
        "must not be negative",
    );
    assert_err(
        &format!("{BASE}spring 2 1 x k=0\n"),
        8,
        16,
        "must be positive",
    );
    assert_err("damping modal -0.01\n", 1, 15, "must not be negative");
}

/// Parameters on IDs that do not exist or quantities that do not apply.
fn parameters_on_missing_ids_or_quantities() {
    assert_err(
        &format!("{BASE}param p E 1-2\n"),
        8,
        11,
        "beam ID 2, which does not exist",
    );
    assert_err(&format!("{BASE}param p Iy 1,4\n"), 8, 14, "beam ID 4");
    assert_err(&format!("{BASE}param p m 2\n"), 8, 11, "mass ID 2");
    assert_err(&format!("{BASE}param p k 1,2\n"), 8, 13, "spring ID 2");
    // `m` on a beam ID: the hint says why.
    assert_err(
        "material m E=1 rho=1\nsection s A=1 Iy=1 Iz=1 J=1\nnode 1 0 0 0\nnode 2 1 0 0\nbeam 5 1 2 m s\nparam p m 5\n",
        6,
        11,
        "does not apply",
    );
}

fn analysis_restrictions() {
    assert_err("analysis plane\nnode 1 0 0.5 0\n", 2, 10, "requires y = 0");
    assert_err("section s A=1 Iy=1 J=1\n", 1, 1, "lacks `Iz=");
    assert_err("section s A=1 Iy=1 Iz=1\n", 1, 1, "lacks `J=");
    assert!(parse("analysis plane\nsection s A=1 Iy=1\n").is_ok());
    let plane = "analysis plane\nmaterial m E=1 rho=1\nsection s A=1 Iy=1\nnode 1 0 0 0\nnode 2 1 0 0\nbeam 1 1 2 m s\n";
    assert_err(
        &format!("{plane}spring 1 1 y k=1\n"),
        7,
        12,
        "does not exist in `analysis plane`",
    );
    assert_err(
        &format!("{plane}fix 1 x,rz\n"),
        7,
        7,
        "does not exist in `analysis plane`",
    );
    assert_err(
        &format!("{plane}param p Iz 1\n"),
        7,
        9,
        "does not apply in `analysis plane`",
    );
    assert_err(&format!("{plane}param p J 1\n"), 7, 9, "does not apply");
    assert_err(
        &format!("{plane}beam 2 1 2 m s orient=0,0,1\n"),
        7,
        23,
        "along global y",
    );
    assert!(parse(&format!("{plane}beam 2 1 2 m s orient=0,-1,0\nfix 1 all\n")).is_ok());
    assert_err(
        &format!("{BASE}beam 2 1 2 m s orient=0,0,0\n"),
        8,
        23,
        "non-zero",
    );
}

#[test]
fn errors_display_line_column_message() {
    let e = parse("node 1 0 0 0\n\n   oops\n").unwrap_err();
    assert_eq!(e.to_string(), format!("3:4: {}", e.message));
}

#[test]
fn comments_blank_lines_tabs_and_crlf() {
    assert_eq!(
        parse("\u{feff}node 1 0 0 0\n").unwrap().nodes[0].pos,
        Pos::new(1, 1)
    );
    let d = parse("# c\r\n\r\n\tnode\t1  0\t0 0 # node\r\n   \r\nnode 2 1 0 0#x\r\n").unwrap();
    assert_eq!(d.nodes.len(), 2);
    assert_eq!(d.nodes[0].pos, Pos::new(3, 2));
    assert_eq!(d.nodes[1].xyz, [1.0, 0.0, 0.0]);
}

#[test]
fn writer_round_trips() {
    let d = parse(FULL).unwrap();
    let text = write(&d);
    let d2 = parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    // Same deck apart from positions: the text is a fixed point.
    assert_eq!(write(&d2), text);
    assert_eq!(d2.materials.len(), d.materials.len());
    for (a, b) in d.materials.iter().zip(&d2.materials) {
        assert_eq!((a.e, a.rho, a.nu, a.g), (b.e, b.rho, b.nu, b.g));
    }
    for (a, b) in d.beams.iter().zip(&d2.beams) {
        assert_eq!(
            (a.nodes, a.theory, a.orient.map(|o| o.vector)),
            (b.nodes, b.theory, b.orient.map(|o| o.vector))
        );
    }
    assert_eq!(d.params.len(), d2.params.len());
    assert_eq!(
        d.param("I").unwrap().ids().collect::<Vec<_>>(),
        d2.param("I").unwrap().ids().collect::<Vec<_>>()
    );
    assert_eq!(d.damping.map(|x| x.model), d2.damping.map(|x| x.model));
    assert_eq!(d.title(), d2.title());
}

#[test]
fn numbers_are_written_with_full_precision() {
    for x in [
        0.1 + 0.2,
        1.0 / 3.0,
        7.2e10,
        -2.5e-13,
        6.02214076e23,
        1e-4,
        9999999.999999998,
        f64::MIN_POSITIVE,
        f64::MAX,
        0.0,
        -0.0,
        2700.0,
    ] {
        let s = format_number(x);
        let d = parse(&format!("node 1 {s} 0 0\n")).unwrap();
        assert_eq!(d.nodes[0].xyz[0].to_bits(), x.to_bits(), "{x} → {s}");
    }
    assert_eq!(format_number(2700.0), "2700");
    assert_eq!(format_number(7.2e10), "7.2e10");
}

#[test]
fn the_documentation_example_parses() {
    let doc = include_str!("../../../docs/deck.md");
    let start = doc.find("```text\n").unwrap() + 8;
    let end = start + doc[start..].find("```").unwrap();
    let d = parse(&doc[start..end]).unwrap();
    assert_eq!(d.analysis, Analysis::Plane);
    assert_eq!(d.params.len(), 2);
}
