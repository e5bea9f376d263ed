//! Per-pixel counts as header text: run-length encoded, because the counts
//! of a render are nearly all equal (every pixel takes the same samples and
//! loses only the few that came out NaN or infinite), so a whole frame's
//! counts fit in a few bytes and only the pixels that differ cost more.
//!
//! The form is whitespace-separated `VALUE` or `VALUE*RUN` tokens, in row
//! order over the data window: `64*767 63 64*200`.

/// Encodes `values` as `VALUE*RUN` tokens (a run of one as plain `VALUE`).
pub fn encode_runs(values: &[u32]) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < values.len() {
        let v = values[i];
        let run = values[i..].iter().take_while(|&&w| w == v).count();
        if !out.is_empty() {
            out.push(' ');
        }
        match run {
            1 => out.push_str(&v.to_string()),
            _ => out.push_str(&format!("{v}*{run}")),
        }
        i += run;
    }
    out
}

/// Decodes exactly `n` values; the reason when the text is not `n` values
/// of the form (never allocating more than `n` values, whatever a run says).
pub fn decode_runs(text: &str, n: usize) -> Result<Vec<u32>, String> {
    let mut out = Vec::with_capacity(n);
    for token in text.split_ascii_whitespace() {
        let (value, run) = match token.split_once('*') {
            Some((v, r)) => (v, r.parse::<usize>().ok().filter(|r| *r > 0)),
            None => (token, Some(1)),
        };
        let (Ok(value), Some(run)) = (value.parse::<u32>(), run) else {
            return Err(format!("`{token}` is not COUNT or COUNT*RUN"));
        };
        if run > n - out.len() {
            return Err(format!("runs cover more than the {n} pixels"));
        }
        out.extend(std::iter::repeat_n(value, run));
    }
    if out.len() != n {
        return Err(format!("runs cover {} of the {n} pixels", out.len()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_round_trip_and_stay_short_for_equal_counts() {
        let mut counts = vec![64u32; 1000];
        counts[767] = 63;
        counts[999] = 0;
        let text = encode_runs(&counts);
        assert_eq!(text, "64*767 63 64*231 0");
        assert_eq!(decode_runs(&text, 1000).unwrap(), counts);
        assert_eq!(encode_runs(&[]), "");
        assert_eq!(decode_runs("", 0).unwrap(), Vec::<u32>::new());
    }

    #[test]
    fn malformed_or_miscounted_runs_are_refused() {
        assert!(decode_runs("64*3", 4)
            .unwrap_err()
            .contains("cover 3 of the 4"));
        assert!(decode_runs("64*5", 4)
            .unwrap_err()
            .contains("more than the 4"));
        // A huge run is refused before anything is allocated for it.
        assert!(decode_runs("1*18446744073709551615", 4).is_err());
        assert!(decode_runs("64*0 1", 1).unwrap_err().contains("64*0"));
        assert!(decode_runs("-1", 1).unwrap_err().contains("-1"));
        assert!(decode_runs("a*2", 2).is_err());
    }
}
