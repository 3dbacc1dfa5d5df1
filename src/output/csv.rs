//! CSV writing with a header row; floats are formatted by the caller ([`super::fmt_float`]).

use crate::error::{Error, Result};
use std::path::Path;

/// Writes a CSV file with `header` and string rows (through [`super::atomic::write_with`]).
pub fn write_rows<I, R>(path: &Path, header: &[&str], rows: I) -> Result<()>
where
    I: IntoIterator<Item = R>,
    R: IntoIterator<Item = String>,
{
    let err = |e: csv::Error| Error::Csv {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    super::atomic::write_with(path, |tmp| {
        let mut w = csv::Writer::from_path(tmp).map_err(err)?;
        w.write_record(header).map_err(err)?;
        for r in rows {
            w.write_record(r).map_err(err)?;
        }
        w.flush().map_err(|e| Error::io(path, e))
    })
}
