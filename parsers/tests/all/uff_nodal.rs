//! Datasets 55, 15 and 82 written then read back by our reader: values to
//! the 6 significant digits of `E13.5`, integers and texts exactly.

use frfup_parsers::uff::{
    self, Complex64, Dataset, NodalData55, Node, NodeValues, Ordinate, OtherKind, TraceLine,
};

fn mode(complex: bool) -> NodalData55 {
    let nodes = (1..=4)
        .map(|n| NodeValues {
            node: n * 10,
            values: if complex {
                Ordinate::Complex(
                    (0..3)
                        .map(|d| Complex64::new(0.1 * (n + d) as f64 - 0.3, -1.5e-4 * d as f64))
                        .collect(),
                )
            } else {
                Ordinate::Real((0..3).map(|d| 1.0 / (n + d) as f64).collect())
            },
        })
        .collect();
    NodalData55 {
        id_lines: [
            "mode 1".into(),
            "frfup identify".into(),
            String::new(),
            "x".repeat(90),
            "NONE".into(),
        ],
        model_type: 1,
        analysis_type: if complex { 3 } else { 2 },
        data_characteristic: 2,
        specific_data_type: 8,
        data_type: if complex { 5 } else { 2 },
        values_per_node: 3,
        integers: vec![1, 7],
        reals: if complex {
            vec![-0.5, 120.25, 0.0, 0.0, 0.0, 0.0]
        } else {
            vec![19.123456, 1.0, 0.0123, 0.0]
        },
        nodes,
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 5e-6 * a.abs().max(b.abs()) + 1e-300
}

#[test]
fn dataset55_round_trip() {
    for complex in [false, true] {
        let d = mode(complex);
        let mut bytes = Vec::new();
        uff::write_nodal_data(&mut bytes, &d).unwrap();
        let file = uff::parse(&bytes).unwrap();
        let [Dataset::Other(o)] = file.datasets.as_slice() else {
            panic!("one dataset expected");
        };
        let OtherKind::NodalData(r) = &o.kind else {
            panic!("dataset 55 expected, got {:?}", o.kind);
        };
        assert_eq!(r.id_lines[0], "mode 1");
        assert_eq!(r.id_lines[2], "NONE", "an empty record is written NONE");
        assert_eq!(r.id_lines[3].len(), 80, "records are cut at 80 columns");
        assert_eq!(
            (r.analysis_type, r.data_type, r.values_per_node),
            (d.analysis_type, d.data_type, 3)
        );
        assert_eq!(r.integers, d.integers);
        assert!(r.reals.iter().zip(&d.reals).all(|(a, b)| close(*a, *b)));
        assert_eq!(r.nodes.len(), d.nodes.len());
        for (a, b) in r.nodes.iter().zip(&d.nodes) {
            assert_eq!(a.node, b.node);
            for i in 0..3 {
                let (x, y) = (a.values.at(i), b.values.at(i));
                assert!(close(x.0, y.0) && close(x.1, y.1), "{x:?} {y:?}");
            }
        }
    }
}

#[test]
fn dataset55_refuses_inconsistent_values() {
    let mut d = mode(false);
    d.values_per_node = 6;
    assert!(uff::write_nodal_data(&mut Vec::new(), &d).is_err());
    let mut d = mode(false);
    d.reals[0] = f64::NAN;
    assert!(uff::write_nodal_data(&mut Vec::new(), &d).is_err());
}

#[test]
fn nodes_and_trace_lines_round_trip() {
    let nodes: Vec<Node> = (1..=3)
        .map(|k| Node {
            label: k,
            definition_cs: 0,
            displacement_cs: 0,
            color: 11,
            coordinates: [0.5 * k as f64, -1.25, 1e-3 * k as f64],
        })
        .collect();
    let line = TraceLine {
        number: 1,
        color: 2,
        id: "wing".into(),
        nodes: (1..=11).map(|k| k % 4).collect(),
    };
    let mut bytes = Vec::new();
    uff::write_nodes15(&mut bytes, &nodes).unwrap();
    uff::write_trace_line82(&mut bytes, &line).unwrap();
    let file = uff::parse(&bytes).unwrap();
    let kinds: Vec<&OtherKind> = file
        .datasets
        .iter()
        .map(|d| match d {
            Dataset::Other(o) => &o.kind,
            Dataset::Function(_) => panic!("no function written"),
        })
        .collect();
    let [OtherKind::Nodes(n), OtherKind::TraceLine(t)] = kinds.as_slice() else {
        panic!("{kinds:?}");
    };
    assert_eq!(n.len(), 3);
    for (a, b) in n.iter().zip(&nodes) {
        assert_eq!((a.label, a.color), (b.label, b.color));
        assert!(a
            .coordinates
            .iter()
            .zip(&b.coordinates)
            .all(|(x, y)| close(*x, *y)));
    }
    assert_eq!(t.nodes, line.nodes);
    assert_eq!(t.id, "wing");
}
