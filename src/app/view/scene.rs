//! The view's settings as scene keys: the page sends the keys of a scene file (the sections
//! and names of [`crate::app::scene`]) as JSON; they are checked against the keys a page may
//! set, merged over the scene the command was started with, and parsed by the scene-file
//! parser into a [`RenderJob`]. The merged table is what "save" writes as TOML, so the saved
//! scene is the job that was rendered.

use std::path::{Path, PathBuf};

use crate::app::scene::{SceneFile, file_beside, no_mesh_given};
use crate::error::{Error, Problem, Result};
use crate::render::RenderJob;
use crate::render::modes::MODE_KEYS;

/// The largest image side the view renders (the page's canvas, clamped by the page).
pub(crate) const MAX_VIEW_SIDE: u32 = 2048;

/// The most samples per pixel the view renders for its converged frame.
pub(crate) const MAX_VIEW_SPP: u32 = 256;

/// The keys a page may set, by section, beside every mode's keys that name no file
/// ([`page_keys`]): no key names a file (no `mesh`, `render.output`, `shaded.environment`),
/// none changes the BVH or what is written (`[bvh]`, `render.exr`, animations), so a page can
/// make the server read or write nothing but its own outputs.
const PAGE_KEYS: &[(&str, &[&str])] = &[
    ("camera", &["eye", "target", "up", "fov", "ortho"]),
    (
        "render",
        &[
            "mode",
            "size",
            "spp",
            "overlay",
            "line_width",
            "seed",
            "background",
            "curves",
            "control_polygons",
            "surface",
            "curve_radius",
            "curve_edge",
        ],
    ),
    ("scheme", &["name", "params"]),
];

/// The keys a page may set in section `name` ([`PAGE_KEYS`], or a mode's keys naming no
/// file); None: the page may not set that section.
fn page_keys(name: &str) -> Option<Vec<&'static str>> {
    if let Some((_, keys)) = PAGE_KEYS.iter().find(|(section, _)| *section == name) {
        return Some(keys.to_vec());
    }
    MODE_KEYS
        .iter()
        .find(|(mode, _)| *mode == name)
        .map(|(_, keys)| keys.iter().filter(|k| !k.file).map(|k| k.name).collect())
}

/// The scene a view starts from: a scene file's keys (its relative paths made absolute) or a
/// bare mesh, with the command line's scheme, parameters and mode.
#[derive(Clone, Debug)]
pub(crate) struct BaseScene {
    /// The scene as a TOML table, paths absolute.
    pub table: toml::Table,
}

/// `path` made absolute (against the working directory) without resolving links.
fn absolute(path: &Path) -> Result<PathBuf> {
    std::path::absolute(path).map_err(|e| Error::io(path, e))
}

impl BaseScene {
    /// The scene of `input` (a `.toml` scene file or a mesh) with `scheme`, `params` and
    /// `mode` (when given) replacing the file's. The scene's output name, animation and EXR
    /// keys are dropped: the view writes only what "save" names.
    pub(crate) fn new(
        input: &Path,
        scheme: Option<&str>,
        params: &[(String, String)],
        mode: Option<&str>,
    ) -> Result<BaseScene> {
        let is_scene = input
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let mut table = if is_scene {
            // Checked as a whole first, with the file's name in the errors.
            SceneFile::load(input)?;
            let text = std::fs::read_to_string(input).map_err(|e| Error::io(input, e))?;
            let mut table: toml::Table = text
                .parse()
                .map_err(|e| Error::Invalid(format!("{}: {e}", input.display())))?;
            let dir = absolute(input)?
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default();
            if let Some(toml::Value::String(mesh)) = table.get("mesh") {
                let mesh = dir.join(mesh);
                table.insert("mesh".into(), path_value(&mesh)?);
            }
            for (name, keys) in MODE_KEYS {
                if let Some(toml::Value::Table(section)) = table.get_mut(*name) {
                    for key in keys.iter() {
                        if let Some(toml::Value::String(file)) = section.get_mut(key.name) {
                            *file = file_beside(key, file, &dir);
                        }
                    }
                }
            }
            table
        } else {
            let mut table = toml::Table::new();
            table.insert("mesh".into(), path_value(&absolute(input)?)?);
            table
        };
        if !table.contains_key("mesh") {
            return Err(no_mesh_given(input));
        }
        if let Some(toml::Value::Table(render)) = table.get_mut("render") {
            for key in [
                "output",
                "exr",
                "exr_compression",
                "turntable",
                "turntable_axis",
                "sweep",
            ] {
                render.remove(key);
            }
        }
        let section = |table: &mut toml::Table, name: &str| -> toml::Table {
            match table.remove(name) {
                Some(toml::Value::Table(t)) => t,
                _ => toml::Table::new(),
            }
        };
        let mut scheme_section = section(&mut table, "scheme");
        if let Some(s) = scheme {
            scheme_section.insert("name".into(), toml::Value::String(s.into()));
        }
        if !params.is_empty() {
            let mut p = match scheme_section.remove("params") {
                Some(toml::Value::Table(t)) => t,
                _ => toml::Table::new(),
            };
            for (name, value) in params {
                p.insert(name.clone(), toml::Value::String(value.clone()));
            }
            scheme_section.insert("params".into(), toml::Value::Table(p));
        }
        table.insert("scheme".into(), toml::Value::Table(scheme_section));
        if let Some(m) = mode {
            let mut render = section(&mut table, "render");
            render.insert("mode".into(), toml::Value::String(m.into()));
            table.insert("render".into(), toml::Value::Table(render));
        }
        let base = BaseScene { table };
        base.scene()?;
        Ok(base)
    }

    /// The scene file of the table.
    pub(crate) fn scene(&self) -> Result<SceneFile> {
        scene_of(&self.table)
    }

    /// This scene with the page's `settings` (a JSON object of sections of scene keys)
    /// merged over it: every section and key checked against the keys a page may set, a
    /// `[scheme]` of the page replacing the base's as a whole. Returns the merged table,
    /// its scene and its validated job (size and samples within the view's bounds).
    pub(crate) fn with_page(
        &self,
        settings: &serde_json::Value,
    ) -> Result<(toml::Table, SceneFile, RenderJob)> {
        let serde_json::Value::Object(sections) = settings else {
            return Err(Error::Invalid("view settings must be a JSON object".into()));
        };
        let mut table = self.table.clone();
        for (name, keys) in sections {
            let allowed = page_keys(name).ok_or_else(|| {
                Error::config(
                    name.as_str(),
                    Problem::Stated {
                        message: format!("the view cannot set the scene section '{name}'"),
                    },
                )
            })?;
            let serde_json::Value::Object(keys) = keys else {
                return Err(Error::Invalid(format!(
                    "view settings: '{name}' must be an object of scene keys"
                )));
            };
            let mut section = match table.remove(name) {
                Some(toml::Value::Table(t)) if name != "scheme" => t,
                _ => toml::Table::new(),
            };
            for (key, value) in keys {
                if !allowed.contains(&key.as_str()) {
                    return Err(Error::config(
                        format!("{name}.{key}"),
                        Problem::Stated {
                            message: format!("the view cannot set the scene key '{name}.{key}'"),
                        },
                    ));
                }
                if value.is_null() {
                    section.remove(key);
                    continue;
                }
                let value = toml::Value::try_from(value)
                    .map_err(|e| Error::Invalid(format!("view settings: '{name}.{key}': {e}")))?;
                section.insert(key.clone(), value);
            }
            table.insert(name.clone(), toml::Value::Table(section));
        }
        let scene = scene_of(&table)?;
        let job = scene.job()?;
        let (w, h, spp) = (job.settings.width, job.settings.height, job.settings.spp);
        if w > MAX_VIEW_SIDE || h > MAX_VIEW_SIDE {
            return Err(Error::config(
                "render.size",
                Problem::Other {
                    text: format!(
                        "{w}x{h}: the view renders at most {MAX_VIEW_SIDE} pixels a side"
                    ),
                },
            ));
        }
        if spp > MAX_VIEW_SPP {
            return Err(Error::config(
                "render.spp",
                Problem::Other {
                    text: format!(
                        "{spp}: the view renders at most {MAX_VIEW_SPP} samples per pixel"
                    ),
                },
            ));
        }
        Ok((table, scene, job))
    }
}

/// A path as a TOML string (paths are written as UTF-8).
fn path_value(path: &Path) -> Result<toml::Value> {
    Ok(toml::Value::String(
        crate::files::utf8_path(path)?.to_string(),
    ))
}

/// The scene file of `table`, parsed by the scene-file parser.
fn scene_of(table: &toml::Table) -> Result<SceneFile> {
    let text = toml::to_string(table)
        .map_err(|e| Error::Invalid(format!("view settings cannot be written as TOML: {e}")))?;
    SceneFile::parse(&text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    fn base() -> BaseScene {
        BaseScene::new(
            Path::new("scenes/icosahedron.obj"),
            Some("hb"),
            &[],
            Some("zebra"),
        )
        .expect("base scene")
    }

    /// The page's keys become the job's settings; the camera's floats survive the trip
    /// through JSON and TOML bit for bit.
    #[test]
    fn page_keys_become_the_job() {
        let eye = [0.1f64 + 0.2, -1.0 / 3.0, 2.5e-7];
        let settings = serde_json::json!({
            "camera": { "eye": eye, "target": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0] },
            "render": { "size": [64, 48], "spp": 1, "mode": "curvature" },
            "zebra": { "stripes": 24 },
        });
        let (table, _, job) = base().with_page(&settings).expect("valid");
        assert_eq!(job.camera.eye, Some(glam::DVec3::from_array(eye)));
        assert_eq!((job.settings.width, job.settings.height), (64, 48));
        assert_eq!(job.settings.mode.name(), "curvature");
        let again = scene_of(&table).expect("parses").job().expect("valid");
        assert_eq!(again.camera, job.camera);
        assert_eq!(again.settings, job.settings);
    }

    /// No key that names a file, the BVH or the outputs can be set from the page; errors
    /// name the key.
    #[test]
    fn file_keys_are_refused() {
        for (settings, fragment) in [
            (serde_json::json!({ "mesh": "/etc/passwd" }), "'mesh'"),
            (
                serde_json::json!({ "render": { "output": "/tmp/x" } }),
                "render.output",
            ),
            (
                serde_json::json!({ "shaded": { "environment": "/tmp/x.exr" } }),
                "shaded.environment",
            ),
            (serde_json::json!({ "bvh": { "max_leaves": 1 } }), "'bvh'"),
            (
                serde_json::json!({ "render": { "size": [4096, 10] } }),
                "at most 2048",
            ),
            (
                serde_json::json!({ "render": { "spp": 1024 } }),
                "at most 256",
            ),
            (
                serde_json::json!({ "zebra": { "duty": 2.0 } }),
                "zebra.duty",
            ),
            (serde_json::json!([1, 2]), "JSON object"),
        ] {
            let err = base()
                .with_page(&settings)
                .expect_err("refused")
                .to_string();
            assert!(err.contains(fragment), "{settings}: {err}");
        }
    }

    /// The page's refusals are typed configuration errors naming the key, in the words the
    /// page has always shown.
    #[test]
    fn refusals_are_config_errors() {
        let refused =
            |settings: serde_json::Value| base().with_page(&settings).expect_err("refused");
        let err = refused(serde_json::json!({ "bvh": { "max_leaves": 1 } }));
        assert_config_error(
            &err,
            "bvh",
            |p| matches!(p, Problem::Stated { .. }),
            "the view cannot set the scene section 'bvh'",
        );
        let err = refused(serde_json::json!({ "render": { "output": "/tmp/x" } }));
        assert_config_error(
            &err,
            "render.output",
            |p| matches!(p, Problem::Stated { .. }),
            "the view cannot set the scene key 'render.output'",
        );
        let err = refused(serde_json::json!({ "render": { "size": [4096, 10] } }));
        assert_config_error(
            &err,
            "render.size",
            |p| matches!(p, Problem::Other { .. }),
            "render.size 4096x10: the view renders at most 2048 pixels a side",
        );
        let err = refused(serde_json::json!({ "render": { "spp": 1024 } }));
        assert_config_error(
            &err,
            "render.spp",
            |p| matches!(p, Problem::Other { .. }),
            "render.spp 1024: the view renders at most 256 samples per pixel",
        );
    }
}
