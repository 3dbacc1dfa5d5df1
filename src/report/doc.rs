//! The report's document: a list of blocks of rich text (inline code, links, bold, subscripts),
//! rendered to Markdown (`index.md`) and to HTML (`index.html`) by hand, so that both show the
//! same content and the HTML has nothing left unrendered.
//!
//! Text is written in a small markup, [`Rich::parse`]: `` `code` ``, `**bold**`,
//! `[text](href)` and `Γ_{C}` (a subscript); everything else is text, escaped for each output.

use std::fmt::Write as _;

/// A piece of inline text.
#[derive(Debug, Clone, PartialEq)]
pub enum Span {
    /// Plain text.
    Text(String),
    /// Inline code.
    Code(String),
    /// Bold text.
    Strong(String),
    /// A link: text, target (relative to the report directory, or `#id`).
    Link(String, String),
    /// A base with a subscript (`Γ_{C}`).
    Sub(String, String),
}

/// Inline rich text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rich(pub Vec<Span>);

impl Rich {
    /// Parses the markup: `` `code` ``, `**bold**`, `[text](href)`, `X_{sub}`. An opening mark
    /// without its closing one is text.
    pub fn parse(s: &str) -> Self {
        let mut out = Rich::default();
        let mut text = String::new();
        let mut rest = s;
        while let Some(c) = rest.chars().next() {
            let parsed = match c {
                '`' => closed(rest, "`", "`").map(|(x, n)| (Span::Code(x.into()), n)),
                '*' if rest.starts_with("**") => {
                    closed(rest, "**", "**").map(|(x, n)| (Span::Strong(x.into()), n))
                }
                '[' => link(rest),
                '_' if rest.starts_with("_{") => closed(rest, "_{", "}").and_then(|(x, n)| {
                    let base = text.pop()?;
                    Some((Span::Sub(base.into(), x.into()), n))
                }),
                _ => None,
            };
            match parsed {
                Some((span, n)) => {
                    out.text_span(std::mem::take(&mut text));
                    out.0.push(span);
                    rest = &rest[n..];
                }
                None => {
                    text.push(c);
                    rest = &rest[c.len_utf8()..];
                }
            }
        }
        out.text_span(text);
        out
    }

    fn text_span(&mut self, t: String) {
        if !t.is_empty() {
            self.0.push(Span::Text(t));
        }
    }

    /// `self` followed by plain `text` (not parsed: data such as error messages).
    pub fn text(mut self, text: impl Into<String>) -> Self {
        self.text_span(text.into());
        self
    }

    /// `self` followed by inline code.
    pub fn code(mut self, code: impl Into<String>) -> Self {
        self.0.push(Span::Code(code.into()));
        self
    }

    /// `self` followed by `other`.
    pub fn and(mut self, other: Rich) -> Self {
        self.0.extend(other.0);
        self
    }

    /// The text without markup (alt texts, ids, titles).
    pub fn plain(&self) -> String {
        self.0
            .iter()
            .map(|s| match s {
                Span::Text(t) | Span::Code(t) | Span::Strong(t) | Span::Link(t, _) => t.clone(),
                Span::Sub(b, x) => format!("{b}{x}"),
            })
            .collect()
    }

    /// Markdown (`table`: inside a table cell, where `|` is escaped).
    pub fn markdown(&self, table: bool) -> String {
        let text = |t: &str| escape_md(t, table);
        self.0
            .iter()
            .map(|s| match s {
                Span::Text(t) => text(t),
                Span::Code(c) if c.contains('`') => format!("`` {c} ``"),
                Span::Code(c) => format!(
                    "`{}`",
                    if table {
                        c.replace('|', "\\|")
                    } else {
                        c.clone()
                    }
                ),
                Span::Strong(t) => format!("**{}**", text(t)),
                Span::Link(t, href) => format!("[{}]({href})", text(t)),
                Span::Sub(b, x) => format!("{}<sub>{}</sub>", text(b), text(x)),
            })
            .collect()
    }

    /// HTML.
    pub fn html(&self) -> String {
        self.0
            .iter()
            .map(|s| match s {
                Span::Text(t) => escape(t),
                Span::Code(c) => format!("<code>{}</code>", escape(c)),
                Span::Strong(t) => format!("<strong>{}</strong>", escape(t)),
                Span::Link(t, href) => format!("<a href=\"{}\">{}</a>", escape(href), escape(t)),
                Span::Sub(b, x) => format!("{}<sub>{}</sub>", escape(b), escape(x)),
            })
            .collect()
    }
}

impl From<&str> for Rich {
    fn from(s: &str) -> Self {
        Rich::parse(s)
    }
}

impl From<String> for Rich {
    fn from(s: String) -> Self {
        Rich::parse(&s)
    }
}

/// The text between `open` at the start of `s` and the next `close`, and the bytes consumed.
fn closed<'a>(s: &'a str, open: &str, close: &str) -> Option<(&'a str, usize)> {
    let body = s.strip_prefix(open)?;
    let end = body.find(close)?;
    (end > 0).then(|| (&body[..end], open.len() + end + close.len()))
}

/// `[text](href)` at the start of `s`.
fn link(s: &str) -> Option<(Span, usize)> {
    let (text, n) = closed(s, "[", "]")?;
    let (href, m) = closed(&s[n..], "(", ")")?;
    Some((Span::Link(text.into(), href.into()), n + m))
}

/// HTML escaping of text and attribute values.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Markdown escaping of text: the characters that could start markup (an underscore only at a
/// word boundary, where it could open emphasis).
fn escape_md(s: &str, table: bool) -> String {
    let chars: Vec<char> = s.chars().collect();
    let mut out = String::with_capacity(s.len());
    for (k, &c) in chars.iter().enumerate() {
        let inside_word = |j: Option<usize>| {
            j.and_then(|j| chars.get(j))
                .is_some_and(|c| c.is_alphanumeric())
        };
        let escaped = match c {
            '\\' | '`' | '*' | '[' | ']' | '<' | '>' => true,
            '|' => table,
            '_' => !(inside_word(k.checked_sub(1)) && inside_word(Some(k + 1))),
            _ => false,
        };
        if escaped {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// Colour of a table cell (a verdict): the text of the cell says the same in words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tone {
    /// No colour.
    #[default]
    Plain,
    /// Meets the expectation.
    Good,
    /// Converges, below the expectation.
    Fair,
    /// Does not converge, or a flagged fit.
    Bad,
    /// No data (run failed, unsupported, too few levels).
    Missing,
}

impl Tone {
    fn class(self) -> Option<&'static str> {
        match self {
            Tone::Plain => None,
            Tone::Good => Some("good"),
            Tone::Fair => Some("fair"),
            Tone::Bad => Some("bad"),
            Tone::Missing => Some("missing"),
        }
    }
}

/// A table cell.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cell {
    /// Lines, each with its own colour (lines joined by `<br>` in HTML, `; ` in Markdown).
    pub lines: Vec<(Rich, Tone)>,
    /// Colour of the whole cell.
    pub tone: Tone,
}

impl Cell {
    /// A plain cell of one line.
    pub fn plain(text: impl Into<Rich>) -> Self {
        Self {
            lines: vec![(text.into(), Tone::Plain)],
            tone: Tone::Plain,
        }
    }
}

impl<T: Into<Rich>> From<T> for Cell {
    fn from(t: T) -> Self {
        Cell::plain(t)
    }
}

/// A figure of the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// PNG file name in the report directory; the SVG beside it has the same stem.
    pub file: String,
    /// The case it belongs to (its section).
    pub case: String,
    /// What is drawn, for readers who cannot see it (the `alt` text).
    pub alt: String,
    /// What is plotted against what, with which reference (markup of [`Rich::parse`]).
    pub caption: String,
}

impl Figure {
    /// The SVG file beside the PNG.
    pub fn svg(&self) -> String {
        match self.file.strip_suffix(".png") {
            Some(stem) => format!("{stem}.svg"),
            None => format!("{}.svg", self.file),
        }
    }
}

/// A block of the document.
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    /// A heading (level 1 to 3) with its anchor id.
    Heading(u8, String, Rich),
    /// A paragraph.
    Para(Rich),
    /// A bulleted list.
    List(Vec<Rich>),
    /// A table: header and rows (in a horizontally scrolling container in HTML).
    Table(Vec<Rich>, Vec<Vec<Cell>>),
    /// A figure with its number.
    Figure(usize, Figure),
    /// The table of contents (the level-2 and level-3 headings).
    Contents,
}

/// A document under construction: unique heading ids and figure numbers.
#[derive(Debug, Default)]
pub struct Doc {
    /// The blocks in order.
    pub blocks: Vec<Block>,
    figures: usize,
}

impl Doc {
    /// Adds a heading; returns its id (a slug of its text, made unique).
    pub fn heading(&mut self, level: u8, text: impl Into<Rich>) -> String {
        let text = text.into();
        let id = text.plain();
        self.heading_id(level, &id, text)
    }

    /// Adds a heading whose id is a slug of `id` (made unique); returns the id.
    pub fn heading_id(&mut self, level: u8, id: &str, text: impl Into<Rich>) -> String {
        let text = text.into();
        let base = slug(id);
        let taken = |id: &str| {
            self.blocks
                .iter()
                .any(|b| matches!(b, Block::Heading(_, i, _) if i == id))
        };
        let mut id = base.clone();
        let mut k = 2;
        while taken(&id) {
            id = format!("{base}-{k}");
            k += 1;
        }
        self.blocks.push(Block::Heading(level, id.clone(), text));
        id
    }

    /// Adds a paragraph.
    pub fn para(&mut self, text: impl Into<Rich>) {
        self.blocks.push(Block::Para(text.into()));
    }

    /// Adds a block.
    pub fn push(&mut self, block: Block) {
        self.blocks.push(block);
    }

    /// Adds a figure, numbered in order.
    pub fn figure(&mut self, figure: Figure) {
        self.figures += 1;
        self.blocks.push(Block::Figure(self.figures, figure));
    }

    /// The level-2 and level-3 headings: `(level, id, text)`.
    fn outline(&self) -> Vec<(u8, &str, &Rich)> {
        self.blocks
            .iter()
            .filter_map(|b| match b {
                Block::Heading(l, id, t) if (2..=3).contains(l) => Some((*l, id.as_str(), t)),
                _ => None,
            })
            .collect()
    }

    /// The document as Markdown (headings carry an `<a id>` anchor so that links agree with the
    /// HTML's).
    pub fn markdown(&self) -> String {
        let mut md = String::new();
        for block in &self.blocks {
            match block {
                Block::Heading(level, id, t) => {
                    let hashes = "#".repeat(*level as usize);
                    let _ = writeln!(
                        md,
                        "<a id=\"{id}\"></a>\n\n{hashes} {}\n",
                        t.markdown(false)
                    );
                }
                Block::Para(p) => {
                    let _ = writeln!(md, "{}\n", p.markdown(false));
                }
                Block::List(items) => {
                    for i in items {
                        let _ = writeln!(md, "- {}", i.markdown(false));
                    }
                    md.push('\n');
                }
                Block::Table(header, rows) => {
                    let cells = |c: &[Rich]| c.iter().map(|x| x.markdown(true)).collect::<Vec<_>>();
                    let _ = writeln!(md, "| {} |", cells(header).join(" | "));
                    let _ = writeln!(md, "|{}", "---|".repeat(header.len()));
                    for r in rows {
                        let r: Vec<String> = r
                            .iter()
                            .map(|c| {
                                let lines: Vec<Rich> =
                                    c.lines.iter().map(|l| l.0.clone()).collect();
                                cells(&lines).join("; ")
                            })
                            .collect();
                        let _ = writeln!(md, "| {} |", r.join(" | "));
                    }
                    md.push('\n');
                }
                Block::Figure(n, f) => {
                    let _ = writeln!(
                        md,
                        "![{}]({})\n\n*Figure {n}.* {} ([SVG]({}))\n",
                        escape_md(&f.alt, false),
                        f.file,
                        Rich::parse(&f.caption).markdown(false),
                        f.svg()
                    );
                }
                Block::Contents => {
                    for (level, id, t) in self.outline() {
                        let indent = if level == 3 { "  " } else { "" };
                        let _ = writeln!(md, "{indent}- [{}](#{id})", t.markdown(false));
                    }
                    md.push('\n');
                }
            }
        }
        md
    }

    /// The document as a standalone HTML page titled `title`.
    pub fn html(&self, title: &str) -> String {
        let mut h = format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
             <title>{}</title>\n<style>{STYLE}</style></head><body>\n",
            escape(title)
        );
        for block in &self.blocks {
            match block {
                Block::Heading(level, id, t) => {
                    let _ = writeln!(h, "<h{level} id=\"{id}\">{}</h{level}>", t.html());
                }
                Block::Para(p) => {
                    let _ = writeln!(h, "<p>{}</p>", p.html());
                }
                Block::List(items) => {
                    h.push_str("<ul>\n");
                    for i in items {
                        let _ = writeln!(h, "<li>{}</li>", i.html());
                    }
                    h.push_str("</ul>\n");
                }
                Block::Table(header, rows) => table_html(&mut h, header, rows),
                Block::Figure(n, f) => {
                    let _ = writeln!(
                        h,
                        "<figure id=\"figure-{n}\"><a href=\"{png}\"><img src=\"{png}\" alt=\"{}\" \
                         loading=\"lazy\"></a><figcaption><strong>Figure {n}.</strong> {} \
                         (<a href=\"{}\">SVG</a>)</figcaption></figure>",
                        escape(&f.alt),
                        Rich::parse(&f.caption).html(),
                        escape(&f.svg()),
                        png = escape(&f.file),
                    );
                }
                Block::Contents => contents_html(&mut h, &self.outline()),
            }
        }
        h.push_str("</body></html>\n");
        h
    }
}

/// The table of contents: level-2 entries, each with its level-3 entries nested.
fn contents_html(h: &mut String, outline: &[(u8, &str, &Rich)]) {
    h.push_str("<nav class=\"toc\"><ul>\n");
    let (mut open_item, mut open_sub) = (false, false);
    for (level, id, t) in outline {
        let link = format!("<a href=\"#{id}\">{}</a>", t.html());
        if *level == 2 {
            if open_sub {
                h.push_str("</ul>");
                open_sub = false;
            }
            if open_item {
                h.push_str("</li>\n");
            }
            h.push_str(&format!("<li>{link}"));
            open_item = true;
        } else {
            if !open_sub {
                h.push_str("<ul>");
                open_sub = true;
            }
            h.push_str(&format!("<li>{link}</li>"));
        }
    }
    if open_sub {
        h.push_str("</ul>");
    }
    if open_item {
        h.push_str("</li>");
    }
    h.push_str("</ul></nav>\n");
}

fn table_html(h: &mut String, header: &[Rich], rows: &[Vec<Cell>]) {
    h.push_str("<div class=\"scroll\"><table>\n<thead><tr>");
    for c in header {
        let _ = write!(h, "<th>{}</th>", c.html());
    }
    h.push_str("</tr></thead>\n<tbody>\n");
    for r in rows {
        h.push_str("<tr>");
        for c in r {
            let class = c
                .tone
                .class()
                .map_or(String::new(), |k| format!(" class=\"{k}\""));
            let body: Vec<String> = c
                .lines
                .iter()
                .map(|(text, tone)| match tone.class() {
                    Some(k) => format!("<span class=\"chip {k}\">{}</span>", text.html()),
                    // One token (a number such as 6.51e-4): not broken at its hyphen.
                    None if !text.html().contains(' ') => {
                        format!("<span class=\"n\">{}</span>", text.html())
                    }
                    None => text.html(),
                })
                .collect();
            let _ = write!(h, "<td{class}>{}</td>", body.join("<br>"));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table></div>\n");
}

/// The page's style: readable width, tables that scroll sideways instead of overflowing,
/// verdict colours.
const STYLE: &str = "body{font-family:system-ui,sans-serif;max-width:1180px;margin:auto;\
padding:0 16px;line-height:1.45;color:#222}\
h1,h2,h3{line-height:1.2}h2{border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:2em}\
code{font-family:ui-monospace,monospace;background:#f3f3f3;padding:0 3px;border-radius:3px;\
font-size:0.92em}\
.scroll{overflow-x:auto;max-width:100%;margin:0.6em 0}\
table{border-collapse:collapse;font-size:0.9em}\
td,th{border:1px solid #bbb;padding:3px 7px;vertical-align:top}th{background:#f0f0f0}\
td.good{background:#d7f0dc}td.fair{background:#fff1c2}td.bad{background:#f7d4d4}\
td.missing{background:#eee;color:#666}.n{white-space:nowrap}\
.chip{display:inline-block;padding:0 4px;margin:1px 0;border-radius:3px;white-space:nowrap;\
font-size:0.95em}\
.chip.good{background:#cdeccf}.chip.fair{background:#ffe9a8}.chip.bad{background:#f5c6c6}\
.chip.missing{background:#e4e4e4;color:#555}\
figure{margin:1.5em 0}img{max-width:100%;height:auto;border:1px solid #ddd}\
figcaption{font-size:0.92em;color:#333;margin-top:4px}\
nav.toc{background:#f7f7f7;border:1px solid #ddd;padding:6px 16px;columns:2;font-size:0.92em}\
nav.toc ul{margin:0;padding-left:1.2em}";

/// A heading's id: lower-case letters and digits, other runs of characters as `-`.
pub fn slug(text: &str) -> String {
    let mut s = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('-') && !s.is_empty() {
            s.push('-');
        }
    }
    let s = s.trim_end_matches('-').to_string();
    if s.is_empty() {
        "section".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_is_parsed_into_spans() {
        let r = Rich::parse("see `summary.csv` and [the table](#orders), **bold**, Γ_{C}, a_b `x");
        assert_eq!(
            r.0,
            vec![
                Span::Text("see ".into()),
                Span::Code("summary.csv".into()),
                Span::Text(" and ".into()),
                Span::Link("the table".into(), "#orders".into()),
                Span::Text(", ".into()),
                Span::Strong("bold".into()),
                Span::Text(", ".into()),
                Span::Sub("Γ".into(), "C".into()),
                Span::Text(", a_b `x".into()),
            ]
        );
        assert_eq!(
            r.html(),
            "see <code>summary.csv</code> and <a href=\"#orders\">the table</a>, \
             <strong>bold</strong>, Γ<sub>C</sub>, a_b `x"
        );
        assert_eq!(
            r.markdown(true),
            "see `summary.csv` and [the table](#orders), **bold**, Γ<sub>C</sub>, a_b \\`x"
        );
    }

    #[test]
    fn text_is_escaped_for_each_output() {
        let r = Rich::default().text("a <b> & *c* | _d_ [e]");
        assert_eq!(r.html(), "a &lt;b&gt; &amp; *c* | _d_ [e]");
        assert_eq!(r.markdown(true), "a \\<b\\> & \\*c\\* \\| \\_d\\_ \\[e\\]");
    }

    #[test]
    fn heading_ids_are_unique_slugs_and_listed_in_the_contents() {
        let mut d = Doc::default();
        d.push(Block::Contents);
        assert_eq!(d.heading(2, "Cases: bar1d"), "cases-bar1d");
        assert_eq!(d.heading(3, "Orders"), "orders");
        assert_eq!(d.heading(3, "Orders"), "orders-2");
        assert_eq!(d.heading(2, "Files"), "files");
        let h = d.html("t");
        assert!(
            h.contains("<li><a href=\"#orders-2\">Orders</a></li>"),
            "{h}"
        );
        assert!(h.contains("<h3 id=\"orders-2\">Orders</h3>"));
        assert_eq!(h.matches("<ul>").count(), h.matches("</ul>").count());
        assert!(d.markdown().contains("  - [Orders](#orders-2)"));
    }
}
