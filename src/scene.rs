//! A scene: meshes by id, one backend, and the last query's contacts.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::backend::{Backend, CpuSelector, QueryMeshes, Selector};
use crate::error::{Error, ErrorKind, Result};
use crate::mesh::{Mesh, Positions};
use crate::query::{self, Contact, QueryStats, Workspace};

/// Id of a mesh. Ids start at 1, are never 0 and never reused (unique in the process).
pub type MeshId = u32;

/// How a scene answers queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneConfig {
    /// Viewing-volume depth in model units; 0 asks for exact intersection (CPU backend).
    pub epsilon: f32,
    /// Leaf size; 0 applies the paper's rule of thumb.
    pub max_polygons_per_box: u32,
}

impl Default for SceneConfig {
    fn default() -> Self {
        SceneConfig {
            epsilon: 0.0,
            max_polygons_per_box: 0,
        }
    }
}

impl SceneConfig {
    /// Checks the values; the message names the field at fault.
    pub fn validate(&self) -> Result<()> {
        if !self.epsilon.is_finite() || self.epsilon < 0.0 {
            return Err(Error::invalid(format!(
                "epsilon is {}; it must be finite and >= 0",
                self.epsilon
            )));
        }
        Ok(())
    }
}

/// Meshes, a backend and the last query's answer.
pub struct Scene {
    config: SceneConfig,
    meshes: BTreeMap<MeshId, Mesh>,
    selector: Box<dyn Selector>,
    workspace: Workspace,
    contacts: Vec<Contact>,
    /// The next answer, built here and swapped into `contacts` on success.
    scratch: Vec<Contact>,
}

impl Scene {
    /// A scene on the CPU backend.
    pub fn new(config: SceneConfig) -> Result<Scene> {
        Scene::with_selector(config, Box::new(CpuSelector::new()))
    }

    /// A scene answering through `selector`.
    pub fn with_selector(config: SceneConfig, selector: Box<dyn Selector>) -> Result<Scene> {
        config.validate()?;
        Ok(Scene {
            config,
            meshes: BTreeMap::new(),
            selector,
            workspace: Workspace::default(),
            contacts: Vec::new(),
            scratch: Vec::new(),
        })
    }

    /// The configuration the scene was made with.
    pub fn config(&self) -> &SceneConfig {
        &self.config
    }

    /// The backend answering the scene's queries.
    pub fn backend(&self) -> Backend {
        self.selector.backend()
    }

    /// Adds a mesh (`vertices_per_polygon` indices per polygon in `indices`).
    pub fn create_mesh(
        &mut self,
        positions: Positions<'_>,
        indices: &[u32],
        vertices_per_polygon: usize,
    ) -> Result<MeshId> {
        let mesh = Mesh::new(
            positions,
            indices,
            vertices_per_polygon,
            self.config.max_polygons_per_box as usize,
        )?;
        let id = fresh_mesh_id().ok_or_else(|| {
            Error::new(
                ErrorKind::Unsupported,
                "this process has used up its 2^32 - 2 mesh ids",
            )
        })?;
        self.meshes.insert(id, mesh);
        Ok(id)
    }

    /// The mesh `id`, or UnknownMesh.
    pub fn mesh(&self, id: MeshId) -> Result<&Mesh> {
        self.meshes.get(&id).ok_or_else(|| unknown(id))
    }

    fn mesh_mut(&mut self, id: MeshId) -> Result<&mut Mesh> {
        self.meshes.get_mut(&id).ok_or_else(|| unknown(id))
    }

    /// Ids of the live meshes, ascending.
    pub fn mesh_ids(&self) -> impl Iterator<Item = MeshId> + '_ {
        self.meshes.keys().copied()
    }

    /// Moves vertices `first..first + positions.len()` and refits the mesh's boxes.
    pub fn update_positions(
        &mut self,
        id: MeshId,
        first: usize,
        positions: Positions<'_>,
    ) -> Result<()> {
        self.mesh_mut(id)?.update_positions(first, positions)?;
        self.selector.mesh_updated(id);
        Ok(())
    }

    /// Enables or disables mesh `id` (a disabled mesh costs nothing in a query).
    pub fn set_enabled(&mut self, id: MeshId, enabled: bool) -> Result<()> {
        self.mesh_mut(id)?.enabled = enabled;
        Ok(())
    }

    /// Removes mesh `id` (its id is never reused).
    pub fn destroy_mesh(&mut self, id: MeshId) -> Result<()> {
        self.meshes
            .remove(&id)
            .map(drop)
            .ok_or_else(|| unknown(id))?;
        self.selector.mesh_destroyed(id);
        Ok(())
    }

    /// GL_COMPUTE: mesh `id` reads its positions (xyz `f32`, `stride` bytes apart from
    /// `offset`, 0 = 12) from the host's buffer object `buffer` at each query.
    pub fn bind_gl_buffer(
        &mut self,
        id: MeshId,
        buffer: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        let m = self.meshes.get(&id).ok_or_else(|| unknown(id))?;
        self.selector.bind_gl_buffer(id, m, buffer, offset, stride)
    }

    /// Deletes the backend's GL objects (GL backends; the scene's context must be current).
    pub fn release_gl(&mut self) {
        self.selector.release();
    }

    /// Collides `reference` with every other enabled mesh. Contacts are sorted by (other
    /// mesh, reference polygon, other polygon), each pair once. A disabled reference has
    /// no contacts.
    pub fn query(&mut self, reference: MeshId) -> Result<&[Contact]> {
        if !self.meshes.contains_key(&reference) {
            return Err(unknown(reference));
        }
        self.selector.take_readbacks();
        let prepared = self.selector.prepare(&mut self.meshes);
        self.workspace.stats = QueryStats::default();
        if let Err(e) = prepared {
            self.workspace.stats.readbacks = self.selector.take_readbacks();
            return Err(e);
        }
        let r = self
            .meshes
            .get(&reference)
            .ok_or_else(|| unknown(reference))?;
        let mut meshes = vec![(reference, r)];
        if r.enabled {
            meshes.extend(
                self.meshes
                    .iter()
                    .filter(|(&id, m)| id != reference && m.enabled)
                    .map(|(&id, m)| (id, m)),
            );
        }
        let q = QueryMeshes {
            meshes,
            half_depth: f64::from(self.config.epsilon) / 2.0,
        };
        // The answer goes to `scratch`, swapped in only on success: after a failed query
        // `contacts()` still holds the last successful query's.
        let res = if q.meshes.len() > 1 {
            query::run(
                self.selector.as_mut(),
                &q,
                &mut self.workspace,
                &mut self.scratch,
            )
        } else {
            self.scratch.clear();
            Ok(())
        };
        if res.is_err() {
            self.workspace.stats = QueryStats::default();
        }
        self.workspace.stats.readbacks = self.selector.take_readbacks();
        res?;
        std::mem::swap(&mut self.scratch, &mut self.contacts);
        Ok(&self.contacts)
    }

    /// The contacts of the last successful query.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// What each step asked and found in the last query.
    pub fn stats(&self) -> QueryStats {
        self.workspace.stats
    }
}

/// Mesh ids come from one process-wide counter: an id is never reused, and an id from
/// another scene is never the id of a live mesh in this one (it answers UNKNOWN_MESH).
static NEXT_MESH_ID: AtomicU32 = AtomicU32::new(1);

fn fresh_mesh_id() -> Option<MeshId> {
    NEXT_MESH_ID
        .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |v| {
            (v < MeshId::MAX).then_some(v + 1)
        })
        .ok()
}

fn unknown(id: MeshId) -> Error {
    Error::new(
        ErrorKind::UnknownMesh,
        format!("mesh id {id} is not in this scene (destroyed, or never created)"),
    )
}
