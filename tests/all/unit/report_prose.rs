//! Unit tests of `src/report/prose.rs` through its public interface.

use frfup::report::prose::*;

#[test]
fn one_sentence_three_formats() {
    let p = Prose::default()
        .text("a < b ")
        .strong("bold")
        .text(" and ")
        .code("x=1");
    assert_eq!(p.markdown(), "a < b **bold** and `x=1`");
    assert_eq!(p.html(), "a &lt; b <b>bold</b> and <code>x=1</code>");
    assert_eq!(p.plain(), "a < b bold and x=1");
}
