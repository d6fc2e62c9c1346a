//! Which schemes a `--scheme` value selects, and the parameters meant for each: shared by the
//! single-mesh commands ([`super`]) and the report's work list ([`super::batch`]).

use crate::error::{Error, Result};
use crate::schemes::{self, SCHEMES};

/// The `--scheme` value that selects every registered scheme.
pub(crate) const ALL_SCHEMES: &str = "all";

/// Parses every `--param name=value`.
pub(crate) fn parse_params(raw: &[String]) -> Result<Vec<(String, String)>> {
    raw.iter().map(|p| schemes::parse_param(p)).collect()
}

/// One scheme to run, with the parameters meant for it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SchemeRun {
    /// Registered scheme name.
    pub scheme: &'static str,
    /// `name=value` pairs for it.
    pub params: Vec<(String, String)>,
}

/// The schemes a `--scheme` value selects, each with the parameters meant for it.
///
/// For one scheme the parameters go to it unchanged (the registry rejects unknown names).
/// For [`ALL_SCHEMES`] each parameter goes to the schemes that declare it, and a parameter
/// that no scheme declares is an error.
pub(crate) fn select_schemes(
    selection: &str,
    params: &[(String, String)],
) -> Result<Vec<SchemeRun>> {
    if selection != ALL_SCHEMES {
        let spec = schemes::find(selection)?;
        return Ok(vec![SchemeRun {
            scheme: spec.name,
            params: params.to_vec(),
        }]);
    }
    if let Some((name, _)) = params
        .iter()
        .find(|(n, _)| !SCHEMES.iter().any(|s| s.params.iter().any(|p| p.name == n)))
    {
        let mut known: Vec<&str> = SCHEMES
            .iter()
            .flat_map(|s| s.params.iter().map(|p| p.name))
            .collect();
        known.sort_unstable();
        known.dedup();
        return Err(Error::UnknownParam {
            scheme: ALL_SCHEMES.to_string(),
            name: name.clone(),
            known: known.join(", "),
        });
    }
    Ok(SCHEMES
        .iter()
        .map(|s| {
            let own = params
                .iter()
                .filter(|(n, _)| s.params.iter().any(|p| p.name == n))
                .cloned()
                .collect();
            SchemeRun {
                scheme: s.name,
                params: own,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(n: &str, v: &str) -> (String, String) {
        (n.to_string(), v.to_string())
    }

    #[test]
    fn one_scheme_keeps_its_params() {
        let sel = select_schemes("pn", &[pair("normals", "obj")]).expect("known");
        let expected = SchemeRun {
            scheme: "pn",
            params: vec![pair("normals", "obj")],
        };
        assert_eq!(sel, vec![expected]);
        let err = select_schemes("nope", &[]).expect_err("unknown scheme");
        assert!(matches!(err, Error::UnknownScheme { .. }), "{err}");
    }

    #[test]
    fn all_routes_params_to_the_schemes_that_declare_them() {
        let sel = select_schemes(ALL_SCHEMES, &[pair("normals", "obj")]).expect("declared");
        assert_eq!(sel.len(), SCHEMES.len());
        for run in &sel {
            let declares = schemes::find(run.scheme)
                .expect("registered")
                .params
                .iter()
                .any(|p| p.name == "normals");
            assert_eq!(run.params.len(), usize::from(declares), "{}", run.scheme);
        }
        let err = select_schemes(ALL_SCHEMES, &[pair("bogus", "1")]).expect_err("undeclared");
        assert!(err.to_string().contains("'bogus'"), "{err}");
    }
}
