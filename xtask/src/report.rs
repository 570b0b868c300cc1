//! What a table command prints and what `--json FILE` writes: markdown
//! tables on standard output, and the same numbers as JSON.
//!
//! Each [`Cell`] carries both its printed text and its JSON value, so the
//! markdown stays exactly what the command printed before `--json` existed
//! while the JSON keeps numbers as numbers (unrounded; NaN and infinities
//! as `null`).

use std::collections::BTreeMap;
use std::fmt::Display;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::{Serialize, Serializer};
use serde_json::{Value, json};

use crate::Spread;

/// A JSON number, or `null` when `x` is NaN or infinite.
pub(crate) fn number(x: f64) -> Value {
    Value::from(x)
}

/// One table cell: the text printed between the pipes and the JSON value
/// written for it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cell {
    text: String,
    value: Value,
}

impl Cell {
    /// A cell printed as `text` and written as `value` (for cells that
    /// hold more than one number).
    pub fn new(text: impl Into<String>, value: Value) -> Cell {
        Cell {
            text: text.into(),
            value,
        }
    }

    /// A number printed as `Display` prints it (integers, λ).
    pub fn shown<T: Display + Into<Value>>(x: T) -> Cell {
        Cell::new(x.to_string(), x.into())
    }

    /// A number printed with `decimals` digits after the point (`{:.3}`).
    pub fn fixed(x: f64, decimals: usize) -> Cell {
        Cell::new(format!("{x:.decimals$}"), number(x))
    }

    /// A number printed in scientific notation (`{:.2e}`).
    pub fn sci(x: f64, decimals: usize) -> Cell {
        Cell::new(format!("{x:.decimals$e}"), number(x))
    }

    /// Text, written as a JSON string (mesh names, `—`).
    pub fn text(text: impl Into<String>) -> Cell {
        let text = text.into();
        Cell::new(text.clone(), Value::String(text))
    }

    /// A number that does not exist here (an unpublished figure, a ratio
    /// to itself): printed as `—`, written as `null`.
    pub fn missing() -> Cell {
        Cell::new("—", Value::Null)
    }

    /// Nothing: printed as an empty cell, written as `null`.
    pub fn empty() -> Cell {
        Cell::new("", Value::Null)
    }

    /// Ratios over rounds: printed as `1.52 (1.40–1.61)`, written as
    /// `{"median": .., "min": .., "max": ..}`.
    pub fn spread(spread: Spread) -> Cell {
        Cell::new(
            spread.to_string(),
            json!({
                "median": number(spread.median),
                "min": number(spread.min),
                "max": number(spread.max),
            }),
        )
    }
}

impl Serialize for Cell {
    /// Only the value: the text is for the markdown.
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.value.serialize(serializer)
    }
}

/// How a column's cells line up in the markdown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Align {
    /// `---`
    Left,
    /// `---:`
    Right,
}

/// A table column: its header cell and alignment.
#[derive(Clone, Debug)]
pub(crate) struct Column {
    name: String,
    align: Align,
}

impl Column {
    /// A left-aligned column (`---`): names, solvers.
    pub fn left(name: &str) -> Column {
        Column {
            name: name.to_string(),
            align: Align::Left,
        }
    }

    /// A right-aligned column (`---:`): numbers.
    pub fn right(name: &str) -> Column {
        Column {
            name: name.to_string(),
            align: Align::Right,
        }
    }

    /// Right-aligned columns, one per name.
    pub fn rights(names: &[&str]) -> Vec<Column> {
        names.iter().map(|name| Column::right(name)).collect()
    }
}

impl Serialize for Column {
    /// Only the name: the alignment is for the markdown.
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.name)
    }
}

/// A table: the sentence printed above it, its columns and its rows.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct Table {
    title: Option<String>,
    columns: Vec<Column>,
    rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table.
    pub fn new(title: Option<String>, columns: Vec<Column>) -> Table {
        Table {
            title,
            columns,
            rows: Vec::new(),
        }
    }

    /// Adds a row of one cell per column.
    pub fn push(&mut self, row: Vec<Cell>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "a row has one cell per column"
        );
        self.rows.push(row);
    }

    /// The title (followed by a blank line), the header line and the
    /// alignment line, each ending in a newline.
    pub fn head(&self) -> String {
        let mut out = String::new();
        if let Some(title) = &self.title {
            out.push_str(title);
            out.push_str("\n\n");
        }
        out.push('|');
        for column in &self.columns {
            out.push_str(&format!(" {} |", column.name));
        }
        out.push_str("\n|");
        for column in &self.columns {
            out.push_str(match column.align {
                Align::Left => "---|",
                Align::Right => "---:|",
            });
        }
        out.push('\n');
        out
    }

    /// One row as a markdown line, without the newline (`| a | 1 | |`:
    /// an empty cell is a single space between its pipes).
    fn row_line(row: &[Cell]) -> String {
        let mut out = String::from("|");
        for cell in row {
            if cell.text.is_empty() {
                out.push_str(" |");
            } else {
                out.push_str(&format!(" {} |", cell.text));
            }
        }
        out
    }

    /// The whole table as markdown, every line ending in a newline: what
    /// [`Report::table`] and [`Report::row`] print as the rows come in.
    #[cfg(test)]
    pub fn markdown(&self) -> String {
        let mut out = self.head();
        for row in &self.rows {
            out.push_str(&Table::row_line(row));
            out.push('\n');
        }
        out
    }
}

/// Where `--json FILE` writes a report, checked before any measurement so
/// that a long run does not fail at its end.
#[derive(Clone, Debug)]
pub(crate) struct JsonFile {
    path: PathBuf,
}

impl JsonFile {
    /// Checks `path`: its folder exists, and it is not an existing file
    /// other than a `.json` one (never over a mesh or anything else).
    pub fn new(path: &Path) -> Result<JsonFile> {
        let json = JsonFile {
            path: path.to_path_buf(),
        };
        json.check()?;
        Ok(json)
    }

    /// The checks of [`JsonFile::new`], again before writing.
    fn check(&self) -> Result<()> {
        let path = &self.path;
        if path.is_dir() {
            bail!("--json {}: is a folder, not a file", path.display());
        }
        let is_json = path.extension().is_some_and(|e| e == "json");
        if path.exists() && !is_json {
            bail!(
                "--json {}: refusing to overwrite an existing file that does not end in .json (a mesh?)",
                path.display()
            );
        }
        let folder = self.folder();
        if !folder.is_dir() {
            bail!(
                "--json {}: folder {} does not exist",
                path.display(),
                folder.display()
            );
        }
        Ok(())
    }

    /// The folder the file goes in (`.` for a bare file name).
    fn folder(&self) -> &Path {
        match self.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        }
    }

    /// Refuses a file in the mesh folder `data`: every later
    /// `cargo xtask load` would try to read it as a mesh.
    fn check_outside(&self, data: &Path) -> Result<()> {
        let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b);
        if same(self.folder(), data) {
            bail!(
                "--json {}: refusing to write into the mesh folder {} (`cargo xtask load` reads every file there)",
                self.path.display(),
                data.display()
            );
        }
        Ok(())
    }

    /// Writes `value` pretty-printed, atomically: to `FILE.tmp` in the
    /// same folder, then renamed over `FILE`.
    fn write(&self, value: &impl Serialize) -> Result<()> {
        self.check()?;
        let mut text = serde_json::to_string_pretty(value).context("serializing the report")?;
        text.push('\n');
        let mut tmp = self.path.clone().into_os_string();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        std::fs::write(&tmp, text).with_context(|| format!("writing {}", tmp.display()))?;
        if let Err(e) = std::fs::rename(&tmp, &self.path) {
            let _ = std::fs::remove_file(&tmp);
            return Err(e)
                .with_context(|| format!("renaming {} to {}", tmp.display(), self.path.display()));
        }
        Ok(())
    }
}

/// Everything one table command prints: its tables, the sentences between
/// them, and sections of numbers printed as prose (the gdist comparison,
/// AVTP's error falls). Printed as it goes; written by [`Report::finish`].
#[derive(Debug, Serialize)]
pub(crate) struct Report {
    /// The xtask command (`bench`, `load`, ..).
    command: String,
    /// `--runs` (`null` for `count`, which has none).
    runs: Option<usize>,
    /// Logical CPUs of the machine, when known.
    logical_cpus: Option<usize>,
    /// The mesh folder.
    geodesics_data: String,
    /// The tables, in printed order.
    tables: Vec<Table>,
    /// Sentences printed outside the tables, trimmed, in printed order.
    notes: Vec<String>,
    /// Named sections of structured numbers.
    #[serde(flatten)]
    sections: BTreeMap<String, Value>,
    /// Where `--json` writes the report, if given.
    #[serde(skip)]
    json: Option<JsonFile>,
}

impl Report {
    /// An empty report of `command` on the meshes of `data`, written to
    /// `json` (if given) when finished. Fails if `json` is in `data`.
    pub fn new(
        command: &str,
        runs: Option<usize>,
        data: &Path,
        json: Option<JsonFile>,
    ) -> Result<Report> {
        if let Some(json) = &json {
            json.check_outside(data)?;
        }
        Ok(Report {
            command: command.to_string(),
            runs,
            logical_cpus: std::thread::available_parallelism().ok().map(|n| n.get()),
            geodesics_data: data.display().to_string(),
            tables: Vec::new(),
            notes: Vec::new(),
            sections: BTreeMap::new(),
            json,
        })
    }

    /// Prints `text` and a newline (as `println!`), and keeps it, trimmed,
    /// as a note unless it is blank.
    pub fn note(&mut self, text: &str) {
        println!("{text}");
        let trimmed = text.trim();
        if !trimmed.is_empty() {
            self.notes.push(trimmed.to_string());
        }
    }

    /// Starts a table and prints its title and header.
    pub fn table(&mut self, title: Option<String>, columns: Vec<Column>) {
        let table = Table::new(title, columns);
        print!("{}", table.head());
        self.tables.push(table);
    }

    /// Adds a row to the table started last and prints it.
    pub fn row(&mut self, row: Vec<Cell>) {
        let table = self
            .tables
            .last_mut()
            .expect("Report::row follows Report::table");
        println!("{}", Table::row_line(&row));
        table.push(row);
    }

    /// Keeps `value` as the top-level section `name`.
    pub fn section(&mut self, name: &str, value: Value) {
        self.sections.insert(name.to_string(), value);
    }

    /// Writes the report to the `--json` file, if one was given.
    pub fn finish(self) -> Result<()> {
        match &self.json {
            Some(json) => json.write(&self),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table with every kind of cell: text, integer, fixed and
    /// scientific numbers (one NaN), a spread, an empty cell.
    fn sample() -> Table {
        let mut table = Table::new(
            Some("A title, best of 3 runs".to_string()),
            vec![
                Column::left("mesh"),
                Column::right("F"),
                Column::right("s"),
                Column::right("speed-up"),
                Column::right("error"),
                Column::right("authors' s"),
                Column::right("note"),
            ],
        );
        table.push(vec![
            Cell::text("bunny.off"),
            Cell::shown(69_666_usize),
            Cell::fixed(0.123_456, 3),
            Cell::spread(Spread {
                median: 1.52,
                min: 1.4,
                max: 1.614,
            }),
            Cell::sci(0.000_123_4, 2),
            Cell::missing(),
            Cell::empty(),
        ]);
        table.push(vec![
            Cell::text("armadillo.obj"),
            Cell::shown(86_482_u64),
            Cell::fixed(f64::NAN, 3),
            Cell::spread(Spread::of(vec![])),
            Cell::sci(0.0, 2),
            Cell::fixed(0.282, 3),
            Cell::shown(2.0),
        ]);
        table
    }

    #[test]
    fn table_prints_as_markdown() {
        insta::assert_snapshot!(sample().markdown());
    }

    #[test]
    fn table_serializes_numbers_as_numbers_and_nan_as_null() {
        let value = serde_json::to_value(sample()).expect("a table serializes");
        let expected = json!({
            "title": "A title, best of 3 runs",
            "columns": ["mesh", "F", "s", "speed-up", "error", "authors' s", "note"],
            "rows": [
                [
                    "bunny.off",
                    69666,
                    0.123456,
                    {"median": 1.52, "min": 1.4, "max": 1.614},
                    0.0001234,
                    null,
                    null
                ],
                [
                    "armadillo.obj",
                    86482,
                    null,
                    {"median": null, "min": null, "max": null},
                    0.0,
                    0.282,
                    2.0
                ]
            ]
        });
        assert_eq!(value, expected);
    }

    #[test]
    fn report_is_written_atomically_and_refuses_other_files() {
        let dir = std::env::temp_dir().join(format!("xtask-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        let path = dir.join("out.json");
        let data = Path::new(env!("CARGO_MANIFEST_DIR"));
        let json = JsonFile::new(&path).expect("a new .json file is accepted");
        let mut report = Report::new("load", Some(1), data, Some(json)).expect("outside data");
        report.table(None, vec![Column::left("mesh"), Column::right("s")]);
        report.row(vec![Cell::text("a.off"), Cell::fixed(f64::INFINITY, 4)]);
        report.section("extra", json!({"ratio": number(0.5)}));
        report.finish().expect("the report is written");
        let text = std::fs::read_to_string(&path).expect("the report exists");
        let value: Value = serde_json::from_str(&text).expect("the report is JSON");
        assert_eq!(value["command"], "load");
        assert_eq!(value["runs"], 1);
        assert_eq!(value["tables"][0]["rows"][0], json!(["a.off", null]));
        assert_eq!(value["extra"]["ratio"], 0.5);
        let mut tmp = path.clone().into_os_string();
        tmp.push(".tmp");
        assert!(!Path::new(&tmp).exists(), "the temporary file is renamed");

        // An existing .json file is replaced; any other existing file is not.
        assert!(JsonFile::new(&path).is_ok());
        let mesh = dir.join("mesh.off");
        std::fs::write(&mesh, "OFF\n").expect("a stand-in mesh");
        assert!(JsonFile::new(&mesh).is_err());
        assert!(JsonFile::new(&dir.join("missing/out.json")).is_err());
        // Nor a file in the mesh folder.
        let inside = JsonFile::new(&path).expect("accepted on its own");
        assert!(Report::new("load", Some(1), &dir, Some(inside)).is_err());
        std::fs::remove_dir_all(&dir).expect("the temporary folder is removed");
    }
}
