//! Progress of long stages on stderr: the Rust twin of sw/include/rtaccel_progress.hpp
//! and rtaccel.regress.Progress (same rules). Nothing for the first 3 s; on a
//! terminal an indicatif bar (rays done / total, percent, elapsed, ETA);
//! otherwise (CI logs, pipes) a plain line at most every 10 s and a last one
//! when the stage ends, if any was printed. RTACCEL_PROGRESS=off|plain|tty
//! overrides the choice (tty still needs a terminal: indicatif draws nothing
//! elsewhere).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

const QUIET: Duration = Duration::from_secs(3);
const PLAIN_EVERY: Duration = Duration::from_secs(10);

pub struct Progress {
    msg: &'static str,
    len: u64,
    done: u64,
    start: Instant,
    next: Duration,
    printed: bool,
    kind: Kind,
}

enum Kind {
    Off,
    Plain,
    Tty(ProgressBar),
}

pub fn bar(len: u64, msg: &'static str) -> Progress {
    let tty = std::io::stderr().is_terminal();
    let kind = match std::env::var("RTACCEL_PROGRESS").as_deref() {
        Ok("off") => Kind::Off,
        Ok("plain") => Kind::Plain,
        _ if tty => {
            // Hidden for the quiet period: drawn from the first update after it.
            let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
            let style =
                "{msg} [{bar:24}] {percent:>3}%  {pos}/{len} rays  {elapsed} elapsed, ETA {eta}";
            pb.set_style(
                ProgressStyle::with_template(style).unwrap_or(ProgressStyle::default_bar()),
            );
            pb.set_message(msg);
            Kind::Tty(pb)
        }
        _ => Kind::Plain,
    };
    Progress {
        msg,
        len,
        done: 0,
        start: Instant::now(),
        next: Duration::ZERO,
        printed: false,
        kind,
    }
}

impl Progress {
    pub fn inc(&mut self, n: u64) {
        self.done += n;
        let t = self.start.elapsed();
        match &self.kind {
            Kind::Off => {}
            Kind::Tty(pb) => {
                if t >= QUIET && !self.printed {
                    pb.set_draw_target(ProgressDrawTarget::stderr());
                    self.printed = true;
                }
                pb.inc(n);
            }
            Kind::Plain => {
                if t >= QUIET && t >= self.next {
                    eprintln!("{}", line(self.msg, self.done, self.len, t));
                    self.next = t + PLAIN_EVERY;
                    self.printed = true;
                }
            }
        }
    }

    /// The last line (plain, if any was printed); a terminal's bar is cleared.
    pub fn finish_and_clear(&self) {
        match &self.kind {
            Kind::Off => {}
            Kind::Tty(pb) => pb.finish_and_clear(),
            Kind::Plain => {
                if self.printed {
                    eprintln!(
                        "{}",
                        line(self.msg, self.done, self.len, self.start.elapsed())
                    );
                }
            }
        }
    }
}

/// "msg  45.1%  29,538/65,536 rays  0:12 elapsed, ETA 0:15", as the C++ and Scala helpers print it.
fn line(msg: &str, done: u64, len: u64, t: Duration) -> String {
    let d = done.min(len);
    let frac = if len > 0 { d as f64 / len as f64 } else { 1.0 };
    let s = t.as_secs_f64();
    let eta = if done > 0 {
        clock(s * (len - d) as f64 / done as f64)
    } else {
        "?".into()
    };
    format!(
        "{msg} {:5.1}%  {}/{} rays  {} elapsed, ETA {eta}",
        100.0 * frac,
        grouped(done),
        grouped(len),
        clock(s)
    )
}

fn grouped(n: u64) -> String {
    let d = n.to_string();
    let mut s = String::new();
    for (i, c) in d.chars().enumerate() {
        if i > 0 && (d.len() - i) % 3 == 0 {
            s.push(',');
        }
        s.push(c);
    }
    s
}

fn clock(s: f64) -> String {
    let t = s.round() as u64;
    if t >= 3600 {
        format!("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
    } else {
        format!("{}:{:02}", t / 60, t % 60)
    }
}
