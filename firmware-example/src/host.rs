//! The host side of a firmware binary: the same loop, trace on stdout, exit code 0 when
//! the run reaches its goal and 1 otherwise (as QEMU's semihosting exit reports it).

use std::io::Write;
use std::process::ExitCode;

struct Stdout(std::io::StdoutLock<'static>);

impl firmware_example::Sink for Stdout {
    fn line(&mut self, line: &[u8]) {
        // A closed pipe ends the trace; the exit code still tells the outcome.
        let _ = self.0.write_all(line).and_then(|()| self.0.write_all(b"\n"));
    }
}

/// Runs the scenario on `image`, printing the trace.
pub fn run(image: &[u8]) -> ExitCode {
    let mut out = Stdout(std::io::stdout().lock());
    let outcome = firmware_example::run(image, &mut out, |_| {});
    let _ = out.0.flush();
    if outcome.reached_goal() { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
