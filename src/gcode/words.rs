//! The words of a G-code line, read as Marlin and Klipper read them: a word is a letter and the
//! number right after it (spaces between the letter and its number, and between words, are
//! optional: `G1X10Y10E1` is `G1 X10 Y10 E1`), letters of either case. A number is digits,
//! signs and points, never an exponent: as for the firmware, `E1e3` is `E1` then `e3`.
//!
//! Nothing here allocates: a line is read as slices of itself, and only the letter compared is
//! upper-cased, so a line of any length costs time linear in its length and no memory.

/// One word of a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Word<'a> {
    /// An ASCII letter, upper-cased; for a character that starts no word (a quote, a `*`, a
    /// digit with no letter before it), that character's first byte.
    pub letter: u8,
    /// The digits, signs and points after the letter (empty when there are none).
    pub number: &'a str,
    /// The word as written, from its letter to the end of its number, or to the next space when
    /// it has no number: what an error names.
    pub text: &'a str,
}

/// The words of `code` (a line without its comment), in order.
#[derive(Debug, Clone)]
pub(super) struct Words<'a> {
    code: &'a str,
    at: usize,
}

impl<'a> Words<'a> {
    /// The words of `code`, from its start.
    pub fn new(code: &'a str) -> Words<'a> {
        Words { code, at: 0 }
    }

    /// The text after the words read so far.
    pub fn rest(&self) -> &'a str {
        &self.code[self.at..]
    }
}

fn is_number_byte(byte: u8) -> bool {
    byte.is_ascii_digit() || matches!(byte, b'.' | b'+' | b'-')
}

impl<'a> Iterator for Words<'a> {
    type Item = Word<'a>;

    fn next(&mut self) -> Option<Word<'a>> {
        let bytes = self.code.as_bytes();
        while self.at < bytes.len() && bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        let start = self.at;
        let &first = bytes.get(start)?;
        if !first.is_ascii_alphabetic() {
            // One character that starts no word (ASCII or not, kept whole).
            let length = self.code[start..].chars().next().map_or(1, char::len_utf8);
            self.at = start + length;
            return Some(Word {
                letter: first,
                number: "",
                text: &self.code[start..self.at],
            });
        }
        let mut at = start + 1;
        while at < bytes.len() && matches!(bytes[at], b' ' | b'\t') {
            at += 1;
        }
        let number_start = at;
        while at < bytes.len() && is_number_byte(bytes[at]) {
            at += 1;
        }
        let number = &self.code[number_start..at];
        let end = if number.is_empty() {
            // No number: the word is the letter; an error names it to the next space.
            self.at = start + 1;
            bytes[start..]
                .iter()
                .position(u8::is_ascii_whitespace)
                .map_or(bytes.len(), |length| start + length)
        } else {
            self.at = at;
            at
        };
        Some(Word {
            letter: first.to_ascii_uppercase(),
            number,
            text: &self.code[start..end],
        })
    }
}

/// A line's code (the text before the first `;`, without a leading line number `N…` and, when
/// there is one, without the checksum `*…` after it) and its comment (the text after that `;`).
pub(super) fn split_line(raw: &str) -> (&str, &str) {
    let (code, comment) = raw.split_once(';').unwrap_or((raw, ""));
    let mut words = Words::new(code);
    match words.next() {
        Some(word) if word.letter == b'N' && !word.number.is_empty() => {
            let rest = words.rest();
            let rest = rest.rfind('*').map_or(rest, |at| &rest[..at]);
            (rest, comment)
        }
        _ => (code, comment),
    }
}

/// A command: `G1`, `M117`, `M862.3` (a letter, a code and maybe a subcode).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Command {
    /// `G`, `M` or `T`.
    pub letter: u8,
    /// The number after it (`G01` is `G1`).
    pub code: u32,
    /// The number after a point, if any (`M862.3`).
    pub subcode: Option<u32>,
}

/// The command `code` starts with and the words after it; `None` when its first word is no
/// command (a Klipper macro such as `PAUSE`, a stray number).
pub(super) fn command(code: &str) -> Option<(Command, Words<'_>)> {
    let mut words = Words::new(code);
    let first = words.next()?;
    if !matches!(first.letter, b'G' | b'M' | b'T') {
        return None;
    }
    let (number, subcode) = match first.number.split_once('.') {
        Some((number, subcode)) => (number, Some(subcode)),
        None => (first.number, None),
    };
    let digits = |text: &str| -> Option<u32> {
        if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        // Any run of digits: leading zeros dropped, a code past `u32` clamped.
        Some(text.parse().unwrap_or(u32::MAX))
    };
    let command = Command {
        letter: first.letter,
        code: digits(number)?,
        subcode: match subcode {
            Some(text) => Some(digits(text)?),
            None => None,
        },
    };
    Some((command, words))
}

/// The words of a command to compare lines with, read once (the pause command).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Pattern(Vec<(u8, String, String)>);

impl Pattern {
    /// The words of `text` (its comment left out).
    pub fn new(text: &str) -> Pattern {
        let (code, _) = split_line(text);
        Pattern(
            Words::new(code)
                .map(|w| (w.letter, w.number.to_string(), pattern_text(&w)))
                .collect(),
        )
    }

    /// Whether the pattern has no words (matches nothing).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Whether `code` has the same words: letters without regard to case, numbers as written,
    /// spaces ignored.
    pub fn matches(&self, code: &str) -> bool {
        let mut words = Words::new(code);
        for (letter, number, text) in &self.0 {
            match words.next() {
                Some(w) if w.letter == *letter && w.number == number => {
                    if !w.letter.is_ascii_alphabetic() && !w.text.eq_ignore_ascii_case(text) {
                        return false;
                    }
                }
                _ => return false,
            }
        }
        words.next().is_none()
    }
}

/// What of a word, beyond its letter and number, a pattern compares: the character of a word
/// that is no letter (its first byte alone would confuse two characters that share it).
fn pattern_text(word: &Word) -> String {
    if word.letter.is_ascii_alphabetic() {
        String::new()
    } else {
        word.text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn letters(code: &str) -> Vec<(char, &str)> {
        Words::new(code)
            .map(|w| (w.letter as char, w.number))
            .collect()
    }

    #[test]
    fn words_need_no_spaces_and_take_no_exponent() {
        let spaced = letters("G1 X10 Y-2.5 E.4");
        assert_eq!(
            spaced,
            [('G', "1"), ('X', "10"), ('Y', "-2.5"), ('E', ".4")]
        );
        assert_eq!(letters("g1x10y-2.5e.4"), spaced);
        assert_eq!(letters("G1X10Y-2.5E.4"), spaced);
        assert_eq!(letters("G 1 X 10\tY-2.5 E .4"), spaced);
        assert_eq!(letters("E1e308"), [('E', "1"), ('E', "308")]);
    }

    #[test]
    fn a_word_without_a_number_is_named_to_the_next_space() {
        let words: Vec<_> = Words::new("G1 X1 Yabc E1").collect();
        assert_eq!(words[2].text, "Yabc");
        assert_eq!(words[2].number, "");
        // The letters after it are words of their own.
        assert_eq!(words[3].letter, b'A');
        let words: Vec<_> = Words::new("M117 «ünïcode» *").collect();
        assert_eq!(words[1].text, "«");
        assert_eq!(words.last().unwrap().text, "*");
    }

    #[test]
    fn commands_line_numbers_and_checksums() {
        let (code, comment) = split_line("N12 G1 X5*71 ; move");
        assert_eq!((code, comment), (" G1 X5", " move"));
        let (command, mut words) = super::command(code).unwrap();
        assert_eq!(
            (command.letter, command.code, command.subcode),
            (b'G', 1, None)
        );
        let word = words.next().unwrap();
        assert_eq!((word.letter, word.number), (b'X', "5"));
        let (command, _) = super::command("G01X5").unwrap();
        assert_eq!((command.code, command.subcode), (1, None));
        let (command, _) = super::command("M862.3 P \"MK3S\"").unwrap();
        assert_eq!((command.code, command.subcode), (862, Some(3)));
        assert!(super::command("PAUSE").is_none());
        assert!(super::command("G1.2.3 X1").is_none());
        let (command, _) = super::command("G99999999999").unwrap();
        assert_eq!(command.code, u32::MAX);
    }

    #[test]
    fn patterns_compare_words() {
        let pause = Pattern::new("M400 U1");
        assert!(pause.matches("m400   u1"));
        assert!(pause.matches("M400U1"));
        assert!(!pause.matches("M400 U1 S2"));
        assert!(!pause.matches("M400"));
        let klipper = Pattern::new("PAUSE");
        assert!(klipper.matches("pause"));
        assert!(!klipper.matches("PAUSED"));
        assert!(Pattern::new("  ; only a comment").is_empty());
        assert!(Pattern::new("M\"x\"").matches("m \"x\""));
        assert!(
            !Pattern::new("M«").matches("M»"),
            "characters that share a first byte"
        );
    }
}
