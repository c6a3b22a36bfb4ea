//! Syntax pass: one statement per line into the typed [`Deck`].

use super::lexer::{id_at, id_list, name_at, number_at, strip_comment, tokenize, Token};
use super::{
    Analysis, Beam, DampingModel, DampingStatement, Deck, DeckDof, DeckError, Fix, FixDofs,
    IdRange, Mass, Material, Node, Orient, Param, Pos, Quantity, Section, Sensor, Spring, Theory,
    Title,
};

const KEYWORDS: &str =
    "title, analysis, material, section, node, beam, mass, spring, fix, damping, param, sensor";

/// Parse every line; the first syntax error stops the parse.
pub(crate) fn parse_statements(text: &str) -> Result<Deck, DeckError> {
    let mut deck = Deck::default();
    for (i, raw) in text.split('\n').enumerate() {
        let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let line = strip_comment(raw);
        let toks = tokenize(line, line_no);
        let Some(first) = toks.first() else { continue };
        statement(&mut deck, line, first, &toks[1..])?;
    }
    Ok(deck)
}

/// One statement (keyword `first`, arguments `args`, from `line`) into `deck`.
fn statement(
    deck: &mut Deck,
    line: &str,
    first: &Token<'_>,
    args: &[Token<'_>],
) -> Result<(), DeckError> {
    match first.text {
        "title" => deck.titles.push(title(line, first, args)),
        "analysis" => analysis(deck, first, args)?,
        "material" => deck.materials.push(material(first, args)?),
        "section" => deck.sections.push(section(first, args)?),
        "node" => deck.nodes.push(node(first, args)?),
        "beam" => deck.beams.push(beam(first, args)?),
        "mass" => deck.masses.push(mass(first, args)?),
        "spring" => deck.springs.push(spring(first, args)?),
        "fix" => deck.fixes.push(fix(first, args)?),
        "damping" => damping(deck, first, args)?,
        "param" => deck.params.push(param(first, args)?),
        "sensor" => deck.sensors.push(sensor(first, args)?),
        other => {
            return Err(DeckError::new(
                first.pos,
                format!("unknown keyword `{other}`: expected one of {KEYWORDS}"),
            ))
        }
    }
    Ok(())
}

/// `title TEXT`: the rest of the line, trailing blanks removed.
fn title(line: &str, first: &Token<'_>, args: &[Token<'_>]) -> Title {
    let text = match args.first() {
        Some(t) => {
            let off = t.text.as_ptr() as usize - line.as_ptr() as usize;
            line[off..].trim_end_matches([' ', '\t']).to_string()
        }
        None => String::new(),
    };
    Title {
        text,
        pos: first.pos,
    }
}

/// `analysis plane|space`, at most once.
fn analysis(deck: &mut Deck, first: &Token<'_>, args: &[Token<'_>]) -> Result<(), DeckError> {
    let [kind] = exact(args, first, &["plane|space"])?;
    let analysis = match kind.text {
        "plane" => Analysis::Plane,
        "space" => Analysis::Space,
        other => {
            return Err(DeckError::new(
                kind.pos,
                format!("expected `plane` or `space`, found `{other}`"),
            ))
        }
    };
    if let Some(prev) = deck.analysis_pos {
        return Err(DeckError::new(
            first.pos,
            format!(
                "duplicate `analysis` statement (first at line {})",
                prev.line
            ),
        ));
    }
    deck.analysis = analysis;
    deck.analysis_pos = Some(first.pos);
    Ok(())
}

/// `node ID X Y Z`.
fn node(first: &Token<'_>, args: &[Token<'_>]) -> Result<Node, DeckError> {
    let [idt, x, y, z] = exact(args, first, &["ID", "X", "Y", "Z"])?;
    Ok(Node {
        id: id_at(idt, "a node ID")?,
        xyz: [
            number_at(x.text, x.pos, "X")?,
            number_at(y.text, y.pos, "Y")?,
            number_at(z.text, z.pos, "Z")?,
        ],
        pos: first.pos,
    })
}

/// `fix NODE DOFS`: `all` or a comma list of DOF names (repeats dropped).
fn fix(first: &Token<'_>, args: &[Token<'_>]) -> Result<Fix, DeckError> {
    let [node, dofs] = exact(args, first, &["NODE", "DOFS"])?;
    let node = id_at(node, "a node ID")?;
    let dofs = if dofs.text == "all" {
        FixDofs::All
    } else {
        let mut list = Vec::new();
        let mut offset = 0;
        for part in dofs.text.split(',') {
            let dof = DeckDof::from_name(part).ok_or_else(|| {
                DeckError::new(
                    dofs.pos_at(offset),
                    format!(
                        "bad DOF name `{part}`: expected `all` or a comma list of x y z rx ry rz"
                    ),
                )
            })?;
            if !list.contains(&dof) {
                list.push(dof);
            }
            offset += part.len() + 1;
        }
        FixDofs::List(list)
    };
    Ok(Fix {
        node,
        dofs,
        pos: first.pos,
    })
}

/// `damping modal ZETA | rayleigh ALPHA BETA | hysteretic ETA`, at most once.
fn damping(deck: &mut Deck, first: &Token<'_>, args: &[Token<'_>]) -> Result<(), DeckError> {
    let Some(kind) = args.first() else {
        return Err(DeckError::new(
            end_of(first),
            "expected `modal ZETA`, `rayleigh ALPHA BETA` or `hysteretic ETA` after `damping`",
        ));
    };
    let values = &args[1..];
    let model = match kind.text {
        "modal" => {
            let [z] = exact(values, kind, &["ZETA"])?;
            DampingModel::Modal {
                zeta: number_at(z.text, z.pos, "ZETA")?,
            }
        }
        "rayleigh" => {
            let [a, b] = exact(values, kind, &["ALPHA", "BETA"])?;
            DampingModel::Rayleigh {
                alpha: number_at(a.text, a.pos, "ALPHA")?,
                beta: number_at(b.text, b.pos, "BETA")?,
            }
        }
        "hysteretic" => {
            let [e] = exact(values, kind, &["ETA"])?;
            DampingModel::Hysteretic {
                eta: number_at(e.text, e.pos, "ETA")?,
            }
        }
        other => {
            return Err(DeckError::new(
                kind.pos,
                format!(
                    "unknown damping model `{other}`: expected `modal`, `rayleigh` or `hysteretic`"
                ),
            ))
        }
    };
    if let Some(prev) = deck.damping {
        return Err(DeckError::new(
            first.pos,
            format!(
                "duplicate `damping` statement (first at line {})",
                prev.pos.line
            ),
        ));
    }
    deck.damping = Some(DampingStatement {
        model,
        pos: first.pos,
    });
    Ok(())
}

/// `param NAME QTY IDS [min=…] [max=…] [sd=…]`.
fn param(first: &Token<'_>, args: &[Token<'_>]) -> Result<Param, DeckError> {
    let (head, tail) = positional(args, first, &["NAME", "QTY", "IDS"])?;
    let [name, qty, ids] = exact(head, first, &["NAME", "QTY", "IDS"])?;
    let kv = KeyValues::parse(tail, first, &["min", "max", "sd"])?;
    let name = name_at(name, "a parameter name")?;
    let quantity = Quantity::from_name(qty.text).ok_or_else(|| {
        DeckError::new(
            qty.pos,
            format!(
                "unknown quantity `{}`: expected one of E G rho A Iy Iz J (beams), m (masses), k (springs)",
                qty.text
            ),
        )
    })?;
    let ids = id_list(ids)?
        .into_iter()
        .map(|(first, last, pos)| IdRange { first, last, pos })
        .collect();
    Ok(Param {
        name,
        quantity,
        ids,
        min: kv.number("min")?,
        max: kv.number("max")?,
        sd: kv.number("sd")?,
        prior_centre: 0.0,
        pos: first.pos,
    })
}

/// `sensor TESTNODE NODE`.
fn sensor(first: &Token<'_>, args: &[Token<'_>]) -> Result<Sensor, DeckError> {
    let [t, n] = exact(args, first, &["TESTNODE", "NODE"])?;
    Ok(Sensor {
        test_node: id_at(t, "a test node ID")?,
        node: id_at(n, "a node ID")?,
        pos: first.pos,
    })
}

/// The column just past a token (where a missing argument was expected).
fn end_of(tok: &Token<'_>) -> Pos {
    tok.pos_at(tok.text.len())
}

/// Exactly `N` positional arguments after `head`.
fn exact<'t, 'a, const N: usize>(
    args: &'t [Token<'a>],
    head: &Token<'a>,
    names: &[&str; N],
) -> Result<&'t [Token<'a>; N], DeckError> {
    if args.len() < N {
        let at = args.last().unwrap_or(head);
        return Err(DeckError::new(
            end_of(at),
            format!(
                "`{}` expects {}; missing {}",
                head.text,
                names.join(" "),
                names[args.len()..].join(" ")
            ),
        ));
    }
    if args.len() > N {
        return Err(DeckError::new(
            args[N].pos,
            format!(
                "unexpected `{}`: `{}` expects {}",
                args[N].text,
                head.text,
                names.join(" ")
            ),
        ));
    }
    args.try_into()
        .map_err(|_| DeckError::new(head.pos, "internal: argument count"))
}

/// `key=value` pairs of a statement, checked against the allowed keys.
struct KeyValues<'a> {
    pairs: Vec<(&'a str, Token<'a>)>,
}

impl<'a> KeyValues<'a> {
    /// Parse `args` as `key=value` pairs with keys from `allowed`.
    fn parse(args: &[Token<'a>], head: &Token<'a>, allowed: &[&str]) -> Result<Self, DeckError> {
        let mut pairs: Vec<(&'a str, Token<'a>)> = Vec::new();
        for tok in args {
            let Some((key, value)) = tok.text.split_once('=') else {
                return Err(DeckError::new(
                    tok.pos,
                    format!(
                        "expected key=value ({}) in `{}`, found `{}`",
                        allowed.join(" "),
                        head.text,
                        tok.text
                    ),
                ));
            };
            if !allowed.contains(&key) {
                return Err(DeckError::new(
                    tok.pos,
                    format!(
                        "unknown key `{key}` in `{}`: expected one of {}",
                        head.text,
                        allowed.join(" ")
                    ),
                ));
            }
            if pairs.iter().any(|(k, _)| *k == key) {
                return Err(DeckError::new(
                    tok.pos,
                    format!("duplicate key `{key}` in `{}`", head.text),
                ));
            }
            let vpos = tok.pos_at(key.len() + 1);
            pairs.push((
                key,
                Token {
                    text: value,
                    pos: vpos,
                },
            ));
        }
        Ok(KeyValues { pairs })
    }

    fn get(&self, key: &str) -> Option<&Token<'a>> {
        self.pairs.iter().find(|(k, _)| *k == key).map(|(_, t)| t)
    }

    fn number(&self, key: &str) -> Result<Option<f64>, DeckError> {
        self.get(key)
            .map(|t| number_at(t.text, t.pos, key))
            .transpose()
    }

    fn required(&self, key: &str, head: &Token<'_>, after: &Token<'_>) -> Result<f64, DeckError> {
        self.number(key)?.ok_or_else(|| {
            DeckError::new(end_of(after), format!("`{}` requires `{key}=…`", head.text))
        })
    }
}

/// Split positional arguments (`n` of them) from the `key=value` tail.
fn positional<'t, 'a>(
    args: &'t [Token<'a>],
    head: &Token<'a>,
    names: &[&str],
) -> Result<(&'t [Token<'a>], &'t [Token<'a>]), DeckError> {
    let n = names.len();
    for (i, tok) in args.iter().take(n).enumerate() {
        if tok.text.contains('=') {
            return Err(DeckError::new(
                tok.pos,
                format!(
                    "expected {} before any key=value, found `{}`",
                    names[i], tok.text
                ),
            ));
        }
    }
    if args.len() < n {
        let at = args.last().unwrap_or(head);
        return Err(DeckError::new(
            end_of(at),
            format!(
                "`{}` expects {}; missing {}",
                head.text,
                names.join(" "),
                names[args.len()..].join(" ")
            ),
        ));
    }
    Ok(args.split_at(n))
}

fn last_token<'t, 'a>(args: &'t [Token<'a>], head: &'t Token<'a>) -> &'t Token<'a> {
    args.last().unwrap_or(head)
}

fn material(head: &Token<'_>, args: &[Token<'_>]) -> Result<Material, DeckError> {
    let (pos_args, rest) = positional(args, head, &["NAME"])?;
    let name = name_at(&pos_args[0], "a material name")?;
    let kv = KeyValues::parse(rest, head, &["E", "rho", "nu", "G"])?;
    let last = last_token(args, head);
    Ok(Material {
        name,
        e: kv.required("E", head, last)?,
        rho: kv.required("rho", head, last)?,
        nu: kv.number("nu")?,
        g: kv.number("G")?,
        pos: head.pos,
    })
}

fn section(head: &Token<'_>, args: &[Token<'_>]) -> Result<Section, DeckError> {
    let (pos_args, rest) = positional(args, head, &["NAME"])?;
    let name = name_at(&pos_args[0], "a section name")?;
    let kv = KeyValues::parse(rest, head, &["A", "Iy", "Iz", "J", "ky", "kz"])?;
    let last = last_token(args, head);
    Ok(Section {
        name,
        a: kv.required("A", head, last)?,
        iy: kv.required("Iy", head, last)?,
        iz: kv.number("Iz")?,
        j: kv.number("J")?,
        ky: kv.number("ky")?,
        kz: kv.number("kz")?,
        pos: head.pos,
    })
}

fn beam(head: &Token<'_>, args: &[Token<'_>]) -> Result<Beam, DeckError> {
    let (p, rest) = positional(args, head, &["ID", "N1", "N2", "MATERIAL", "SECTION"])?;
    let kv = KeyValues::parse(rest, head, &["orient", "theory"])?;
    let orient = match kv.get("orient") {
        None => None,
        Some(tok) => {
            let parts: Vec<&str> = tok.text.split(',').collect();
            if parts.len() != 3 {
                return Err(DeckError::new(
                    tok.pos,
                    format!(
                        "expected orient=VX,VY,VZ (three numbers), found `{}`",
                        tok.text
                    ),
                ));
            }
            let mut v = [0.0; 3];
            let mut offset = 0;
            for (i, part) in parts.iter().enumerate() {
                v[i] = number_at(part, tok.pos_at(offset), "an orient component")?;
                offset += part.len() + 1;
            }
            Some(Orient {
                vector: v,
                pos: tok.pos,
            })
        }
    };
    let theory = match kv.get("theory") {
        None => None,
        Some(tok) => Some(match tok.text {
            "eb" => Theory::EulerBernoulli,
            "timoshenko" => Theory::Timoshenko,
            other => {
                return Err(DeckError::new(
                    tok.pos,
                    format!("unknown beam theory `{other}`: expected `eb` or `timoshenko`"),
                ))
            }
        }),
    };
    Ok(Beam {
        id: id_at(&p[0], "a beam ID")?,
        nodes: [id_at(&p[1], "a node ID")?, id_at(&p[2], "a node ID")?],
        material: name_at(&p[3], "a material name")?,
        section: name_at(&p[4], "a section name")?,
        orient,
        theory,
        pos: head.pos,
    })
}

fn mass(head: &Token<'_>, args: &[Token<'_>]) -> Result<Mass, DeckError> {
    let (p, rest) = positional(args, head, &["ID", "NODE"])?;
    let kv = KeyValues::parse(rest, head, &["m", "Ixx", "Iyy", "Izz"])?;
    let last = last_token(args, head);
    Ok(Mass {
        id: id_at(&p[0], "a mass ID")?,
        node: id_at(&p[1], "a node ID")?,
        m: kv.required("m", head, last)?,
        ixx: kv.number("Ixx")?,
        iyy: kv.number("Iyy")?,
        izz: kv.number("Izz")?,
        pos: head.pos,
    })
}

fn spring(head: &Token<'_>, args: &[Token<'_>]) -> Result<Spring, DeckError> {
    let (p, rest) = positional(args, head, &["ID", "NODE", "DOF"])?;
    let kv = KeyValues::parse(rest, head, &["k", "to"])?;
    let last = last_token(args, head);
    let dof = DeckDof::from_name(p[2].text).ok_or_else(|| {
        DeckError::new(
            p[2].pos,
            format!(
                "bad DOF name `{}`: expected one of x y z rx ry rz",
                p[2].text
            ),
        )
    })?;
    let to = kv
        .get("to")
        .map(|t| id_at(t, "a node ID after to="))
        .transpose()?;
    Ok(Spring {
        id: id_at(&p[0], "a spring ID")?,
        node: id_at(&p[1], "a node ID")?,
        dof,
        k: kv.required("k", head, last)?,
        to,
        pos: head.pos,
    })
}
