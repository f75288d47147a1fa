//! Reading users' scattered data: CSV lines `u,v,x,y,z` (a header line is skipped,
//! `#` starts a comment).

use std::path::Path;

use crate::error::{Error, Location, Result};

/// Parameters (u, v) and points (x, y, z).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScatteredData {
    pub params: Vec<[f64; 2]>,
    pub points: Vec<[f64; 3]>,
}

/// Parses CSV text; `path` only names the source in errors.
///
/// Errors: `Parse` naming the line for a line that does not have five finite numbers
/// (except a non-numeric first line, taken as a header); `InvalidInput` for no data.
pub fn parse_csv(path: &Path, text: &str) -> Result<ScatteredData> {
    let mut d = ScatteredData::default();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split([',', ';', '\t']).map(str::trim).collect();
        let nums: std::result::Result<Vec<f64>, _> =
            fields.iter().map(|f| f.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() == 5 && v.iter().all(|x| x.is_finite()) => {
                d.params.push([v[0], v[1]]);
                d.points.push([v[2], v[3], v[4]]);
            }
            Err(_) if d.params.is_empty() && i == 0 => continue,
            _ => {
                return Err(Error::parse(
                    path,
                    Location::Line(i + 1),
                    format!("expected five finite numbers u,v,x,y,z, got {line:?}"),
                ))
            }
        }
    }
    if d.params.is_empty() {
        return Err(Error::InvalidInput(format!(
            "{}: no data lines",
            path.display()
        )));
    }
    Ok(d)
}

/// Reads a CSV file (the file is never modified).
///
/// Errors: `Io` if it cannot be read; as [`parse_csv`].
pub fn read_csv(path: &Path) -> Result<ScatteredData> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_csv(path, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_comments_and_errors() {
        let p = Path::new("t.csv");
        let d = parse_csv(p, "u,v,x,y,z\n0,0,1,2,3 # a\n\n0.5;1;4;5;6\n").unwrap();
        assert_eq!(d.params, vec![[0.0, 0.0], [0.5, 1.0]]);
        assert_eq!(d.points[1], [4.0, 5.0, 6.0]);
        let e = parse_csv(p, "0,0,1,2,3\n0,0,1,2\n").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        assert!(parse_csv(p, "0,0,1,2,nan\n").is_err());
        assert!(parse_csv(p, "u,v,x,y,z\n").is_err());
    }
}
