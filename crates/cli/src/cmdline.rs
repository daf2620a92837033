//! Command-line hygiene shared by the commands: argument checks made before
//! any computation, and a quiet end on a closed pipe.

/// Checks `--times`: positive, finite and strictly increasing (a reordered
/// list is an error, not silently sorted). The error names the first bad value.
pub fn check_times(times: &[f64]) -> Result<(), String> {
    if times.is_empty() {
        return Err("--times: give at least one output time (s)".into());
    }
    for (k, &t) in times.iter().enumerate() {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!(
                "--times: value {} is {t}; output times must be positive and finite (s)",
                k + 1
            ));
        }
    }
    check_increasing("--times", times)
}

/// Checks that output times are strictly increasing (a reordered or
/// repeated time is an error, not silently sorted or dropped); `key` (the
/// flag or case-file key) starts the error, which names the first value
/// out of order.
pub fn check_increasing(key: &str, times: &[f64]) -> Result<(), String> {
    for (k, w) in times.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(format!(
                "{key}: {} s (value {}) does not come after {} s; give the output times in increasing order",
                w[1],
                k + 2,
                w[0]
            ));
        }
    }
    Ok(())
}

/// Checks `--yield`: a positive stress in Pa.
pub fn check_yield(y: f64) -> Result<(), String> {
    if y.is_finite() && y > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "--yield {y}: the yield stress must be a positive number of pascals (e.g. 250e6)"
        ))
    }
}

/// Whether a panic message is the standard library's report of a failed
/// write to a closed stdout or stderr.
pub fn is_broken_pipe_message(msg: &str) -> bool {
    (msg.contains("failed printing to stdout") || msg.contains("failed printing to stderr"))
        && (msg.contains("Broken pipe") || msg.contains("os error 32"))
}

/// Exit status after a closed pipe: 128 + SIGPIPE, as a shell reports a
/// program ended by the signal.
pub const BROKEN_PIPE_EXIT: i32 = 141;

/// Installs a panic hook that turns the standard library's panic on a closed
/// pipe (`print!` to a reader that went away, as in `tecon … | head -1`)
/// into a quiet exit with status 141; every other panic is reported as before.
pub fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let msg = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if is_broken_pipe_message(msg) {
            std::process::exit(BROKEN_PIPE_EXIT);
        }
        default(info);
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_must_increase_and_the_error_names_the_value() {
        assert!(check_times(&[1.0, 10.0, 600.0]).is_ok());
        let e = check_times(&[600.0, 10.0, 60.0]).unwrap_err();
        assert!(
            e.contains("10 s") && e.contains("600 s") && e.contains("increasing"),
            "{e}"
        );
        assert!(check_times(&[1.0, 1.0]).is_err());
        assert!(check_times(&[-1.0]).unwrap_err().contains("positive"));
        assert!(check_times(&[]).is_err());
        assert!(
            check_yield(250e6).is_ok()
                && check_yield(0.0).is_err()
                && check_yield(f64::NAN).is_err()
        );
    }

    #[test]
    fn the_broken_pipe_panic_is_recognised_and_others_are_not() {
        assert!(is_broken_pipe_message(
            "failed printing to stdout: Broken pipe (os error 32)"
        ));
        assert!(!is_broken_pipe_message("index out of bounds"));
    }
}
