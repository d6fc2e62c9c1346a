//! Where a report comes from: the machine its timings were measured on, the source state
//! (commit with a dirty flag) and the tool version. [`super::compare`] judges timings only
//! between reports of the same [`Machine`].

use std::path::Path;

use serde::{Deserialize, Serialize};

/// The fingerprint of the machine a report's timings were measured on. Two reports with equal
/// fingerprints have comparable timings; any difference (another CPU model, core count,
/// operating system or architecture) makes them incomparable.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Machine {
    /// CPU model (`model name` of `/proc/cpuinfo`), or `unknown` where it cannot be read.
    pub cpu: String,
    /// Logical cores available to the process.
    pub logical_cores: usize,
    /// Operating system (`linux`, `macos`, …).
    pub os: String,
    /// CPU architecture (`x86_64`, `aarch64`, …).
    pub arch: String,
}

impl Machine {
    /// The machine this process runs on.
    pub fn current() -> Machine {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|text| cpu_model(&text))
            .unwrap_or_else(|| "unknown".to_string());
        Machine {
            cpu,
            logical_cores: std::thread::available_parallelism().map_or(0, |n| n.get()),
            os: std::env::consts::OS.to_string(),
            arch: std::env::consts::ARCH.to_string(),
        }
    }

    /// One line: `CPU, N logical cores, os/arch`.
    pub fn describe(&self) -> String {
        format!(
            "{}, {} logical cores, {}/{}",
            self.cpu, self.logical_cores, self.os, self.arch
        )
    }
}

/// The CPU model named by the first `model name` line (x86) or, failing that, the first
/// `Hardware`, `cpu model` or `Model` line (other architectures) of `/proc/cpuinfo` text.
fn cpu_model(cpuinfo: &str) -> Option<String> {
    ["model name", "Hardware", "cpu model", "Model"]
        .iter()
        .find_map(|key| {
            cpuinfo.lines().find_map(|line| {
                let (name, value) = line.split_once(':')?;
                (name.trim() == *key && !value.trim().is_empty()).then(|| value.trim().to_string())
            })
        })
        .map(|model| model.split_whitespace().collect::<Vec<_>>().join(" "))
}

/// `git describe --always --dirty` of the working tree: the commit, with `-dirty` when files
/// differ from it; `unknown` outside a checkout or without git.
pub fn git_describe() -> String {
    git_describe_in(Path::new("."))
}

/// [`git_describe`] of the checkout holding `dir`.
fn git_describe_in(dir: &Path) -> String {
    std::process::Command::new("git")
        .args(["describe", "--always", "--dirty"])
        .current_dir(dir)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The version of this build of smoothlab (from `Cargo.toml`).
pub fn tool_version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cpu_model_is_read_from_cpuinfo() {
        let x86 = "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R)  \
                   CPU @ 2.20GHz\nflags\t\t: fpu\n\nprocessor\t: 1\nmodel name\t: other\n";
        assert_eq!(
            cpu_model(x86).as_deref(),
            Some("Intel(R) Xeon(R) CPU @ 2.20GHz")
        );
        let arm = "processor\t: 0\nBogoMIPS\t: 48.00\n\nHardware\t: BCM2835\nModel\t: Pi 4\n";
        assert_eq!(cpu_model(arm).as_deref(), Some("BCM2835"));
        assert_eq!(cpu_model("processor\t: 0\n"), None);
    }

    #[test]
    fn this_machine_has_a_fingerprint() {
        let machine = Machine::current();
        assert!(machine.logical_cores >= 1);
        assert_eq!(machine.arch, std::env::consts::ARCH);
        assert_eq!(machine, Machine::current(), "stable within a process");
        assert!(machine.describe().contains("logical cores"));
    }

    #[test]
    fn the_describe_string_names_the_commit_or_says_unknown() {
        let outside =
            std::env::temp_dir().join(format!("smoothlab-describe-{}", std::process::id()));
        std::fs::create_dir_all(&outside).unwrap();
        let in_tmp = git_describe_in(&outside);
        std::fs::remove_dir_all(&outside).unwrap();
        let git_works = std::process::Command::new("git")
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success());
        let here = git_describe_in(Path::new(env!("CARGO_MANIFEST_DIR")));
        let in_checkout = Path::new(env!("CARGO_MANIFEST_DIR")).join(".git").exists();
        if git_works && in_checkout {
            let commit = here.trim_end_matches("-dirty");
            assert!(
                commit.len() >= 7
                    && commit
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "-.".contains(c)),
                "{here}"
            );
        } else {
            assert_eq!(here, "unknown");
        }
        // Outside any checkout (a temporary folder, unless it lies inside one).
        let tmp_in_checkout = std::process::Command::new("git")
            .args(["rev-parse", "--git-dir"])
            .current_dir(std::env::temp_dir())
            .output()
            .is_ok_and(|o| o.status.success());
        if !tmp_in_checkout {
            assert_eq!(in_tmp, "unknown");
        }
    }
}
