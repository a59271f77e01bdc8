//! The learning curve: one row per generation, written and read as CSV with the
//! columns `generation,episodes,best_fitness,best_length`.

use std::io;

/// What a generation ended with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GenerationLog {
    /// 0 for the initial population.
    pub generation: u32,
    /// Episodes (unique simulations) spent so far, this generation's included: the
    /// x-axis of the paper's curves.
    pub episodes: u64,
    /// Fitness of the best individual in the population.
    pub best_fitness: f64,
    /// Its length in nodes (closing tokens not counted).
    pub best_length: usize,
}

/// The header line, exactly.
pub const CSV_HEADER: &str = "generation,episodes,best_fitness,best_length";

impl GenerationLog {
    /// The row as a CSV line without the newline. Fitness is written in Rust's
    /// shortest exact form, so reading it back gives the same `f64`.
    #[must_use]
    pub fn csv_row(&self) -> String {
        format!("{},{},{},{}", self.generation, self.episodes, self.best_fitness, self.best_length)
    }
}

/// The whole CSV: header and one line per row, each ending in `\n`.
#[must_use]
pub fn to_csv(rows: &[GenerationLog]) -> String {
    let mut s = String::with_capacity(32 * (rows.len() + 1));
    s.push_str(CSV_HEADER);
    s.push('\n');
    for row in rows {
        s.push_str(&row.csv_row());
        s.push('\n');
    }
    s
}

/// Writes [`to_csv`] to `out`.
///
/// # Errors
/// Whatever `out` returns.
pub fn write_csv<W: io::Write>(rows: &[GenerationLog], mut out: W) -> io::Result<()> {
    out.write_all(to_csv(rows).as_bytes())
}

/// A CSV learning curve that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CsvError {
    /// The first line is not [`CSV_HEADER`].
    #[error("line 1: expected the header `{CSV_HEADER}`, found `{0}`")]
    Header(String),
    /// A row without four fields, or a field that does not parse.
    #[error("line {line}: {what} in `{text}`")]
    Row {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        what: &'static str,
        /// The line.
        text: String,
    },
}

/// Reads a learning curve written by [`to_csv`] (trailing blank lines allowed).
///
/// # Errors
/// [`CsvError`] naming the line.
pub fn read_csv(text: &str) -> Result<Vec<GenerationLog>, CsvError> {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("").trim_end();
    if header != CSV_HEADER {
        return Err(CsvError::Header(header.to_string()));
    }
    let mut rows = Vec::new();
    for (i, raw) in lines.enumerate() {
        let text = raw.trim_end();
        if text.is_empty() {
            continue;
        }
        let line = i + 2;
        let bad = |what| CsvError::Row { line, what, text: text.to_string() };
        let fields: Vec<&str> = text.split(',').collect();
        let [g, e, f, l] = fields.as_slice() else {
            return Err(bad("expected 4 fields"));
        };
        rows.push(GenerationLog {
            generation: g.parse().map_err(|_| bad("bad generation"))?,
            episodes: e.parse().map_err(|_| bad("bad episodes"))?,
            best_fitness: f.parse().map_err(|_| bad("bad best_fitness"))?,
            best_length: l.parse().map_err(|_| bad("bad best_length"))?,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_exactly() {
        let rows = [
            GenerationLog { generation: 0, episodes: 16, best_fitness: -52.300000000000004, best_length: 8 },
            GenerationLog { generation: 1, episodes: 47, best_fitness: -0.1, best_length: 11 },
            GenerationLog { generation: 2, episodes: 47, best_fitness: f64::NEG_INFINITY, best_length: 3 },
        ];
        let text = to_csv(&rows);
        assert!(text.starts_with("generation,episodes,best_fitness,best_length\n0,16,-52.300000000000004,8\n"));
        assert_eq!(read_csv(&text), Ok(rows.to_vec()));
        let mut buf = Vec::new();
        write_csv(&rows, &mut buf).unwrap();
        assert_eq!(buf, text.as_bytes());
    }

    #[test]
    fn csv_errors_name_the_line() {
        assert!(matches!(read_csv("gen,ep\n"), Err(CsvError::Header(_))));
        assert!(matches!(read_csv(""), Err(CsvError::Header(_))));
        let e = read_csv(&format!("{CSV_HEADER}\n0,16,-1,8\n1,x,-1,8\n")).unwrap_err();
        assert_eq!(e, CsvError::Row { line: 3, what: "bad episodes", text: "1,x,-1,8".into() });
        assert!(matches!(read_csv(&format!("{CSV_HEADER}\n0,16,-1\n")), Err(CsvError::Row { line: 2, .. })));
    }
}
