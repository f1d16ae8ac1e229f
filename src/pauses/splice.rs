//! Lines added to a file's bytes, the rest copied as it is.

/// The line break `bytes` use: `\r\n` when their first line ends so, else `\n`.
pub(super) fn line_break(bytes: &[u8]) -> &'static [u8] {
    let crlf = bytes
        .iter()
        .position(|&b| b == b'\n')
        .is_some_and(|at| at > 0 && bytes[at - 1] == b'\r');
    if crlf {
        b"\r\n"
    } else {
        b"\n"
    }
}

/// How many lines `bytes` hold (their line breaks).
fn line_count(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| b == b'\n').count()
}

/// `bytes` with each of `additions` (1-based line, lines to put before it; sorted by line) put
/// in, and the map from a line of the input to its line in the output.
pub(super) fn splice(
    bytes: &[u8],
    additions: &[(usize, Vec<u8>)],
) -> (Vec<u8>, impl Fn(usize) -> usize) {
    let extra: usize = additions.iter().map(|(_, lines)| lines.len()).sum();
    let mut output = Vec::with_capacity(bytes.len() + extra);
    let mut line = 1;
    let mut copied = 0;
    let mut pending = additions.iter().peekable();
    while let Some((_, lines)) = pending.next_if(|(before, _)| *before <= 1) {
        output.extend_from_slice(lines);
    }
    for (at, _) in bytes.iter().enumerate().filter(|(_, &b)| b == b'\n') {
        // `at + 1` starts line `line + 1`.
        line += 1;
        while let Some((before, lines)) = pending.peek() {
            if *before > line {
                break;
            }
            output.extend_from_slice(&bytes[copied..=at]);
            copied = at + 1;
            output.extend_from_slice(lines);
            pending.next();
        }
    }
    output.extend_from_slice(&bytes[copied..]);
    let shifts: Vec<(usize, usize)> = additions
        .iter()
        .map(|(before, lines)| (*before, line_count(lines)))
        .collect();
    let shift = move |line: usize| {
        line + shifts
            .iter()
            .filter(|(before, _)| *before <= line)
            .map(|(_, count)| count)
            .sum::<usize>()
    };
    (output, shift)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_go_before_their_line_and_lines_are_mapped_past_them() {
        let input = b"a\nb\nc";
        let additions = [(1, b"0\n".to_vec()), (3, b"x\ny\n".to_vec())];
        let (output, shift) = splice(input, &additions);
        assert_eq!(output, b"0\na\nb\nx\ny\nc");
        assert_eq!([shift(1), shift(2), shift(3)], [2, 3, 6]);
        assert_eq!(line_break(b"G1\r\nG2\n"), b"\r\n");
        assert_eq!(line_break(b"G1\nG2\r\n"), b"\n");
        assert_eq!(line_break(b"G1"), b"\n");
    }
}
