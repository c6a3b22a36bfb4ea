//! Unit tests of `src/testdata/layout.rs` through its public interface.

use faer::c64;
use frfup::testdata::dof_label;
use frfup::testdata::layout::*;
use frfup::testdata::MeasuredFrfs;
use frfup::testdata::{Channel, FrfKind};

fn ch(resp: (i64, i32), reference: (i64, i32), v: f64) -> Channel {
    Channel {
        response_node: resp.0,
        response_direction: resp.1,
        reference_node: reference.0,
        reference_direction: reference.1,
        values: vec![c64::new(v, -v)],
    }
}

fn frfs(channels: Vec<Channel>) -> MeasuredFrfs {
    MeasuredFrfs {
        frequencies_hz: vec![10.0],
        kind: FrfKind::Accelerance,
        channels,
    }
}

#[test]
fn a_row_becomes_the_column_of_the_response_dof() {
    let t = frfs(vec![
        ch((5, 3), (1, 3), 1.0),
        ch((5, 3), (2, -3), 2.0),
        ch((5, 3), (5, 3), 3.0),
    ]);
    let (c, layout) = as_column(&t);
    assert_eq!(
        layout,
        Layout::RovingHammer {
            response: dof_label(5, 3),
            impacts: 3
        }
    );
    let got: Vec<_> = c
        .channels
        .iter()
        .map(|x| {
            (
                x.response_node,
                x.response_direction,
                x.reference_node,
                x.reference_direction,
                x.values[0].re,
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![(1, 3, 5, 3, 1.0), (2, -3, 5, 3, 2.0), (5, 3, 5, 3, 3.0)]
    );
}

#[test]
fn a_column_and_mimo_are_kept() {
    let t = frfs(vec![ch((1, 3), (5, 3), 1.0), ch((2, 3), (5, 3), 1.0)]);
    assert_eq!(as_column(&t).0, t);
    assert!(matches!(
        as_column(&t).1,
        Layout::FixedExciter { channels: 2, .. }
    ));
    let m = frfs(vec![
        ch((1, 3), (5, 3), 1.0),
        ch((2, 3), (6, 3), 1.0),
        ch((3, 3), (6, 3), 1.0),
    ]);
    let (c, layout) = as_column(&m);
    assert_eq!(c, m);
    assert_eq!(
        layout,
        Layout::MultiReference {
            used: dof_label(6, 3),
            channels: 2,
            references: 2,
            set_aside: 1
        }
    );
}
