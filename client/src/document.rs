//! Descriptions in other formats (docs/design.md §6.3): [`DocumentFormat`] for the create
//! options, and [`Client::convert_document`], which shows the assembly JSON the server
//! builds from an MJCF description.

use gymfleet_proto::v1 as pb;

use crate::client::Client;
use crate::Result;

/// The format of a document given to `create_env`/`create_batch`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum DocumentFormat {
    /// The server detects it: XML whose root is `<mujoco>` is MJCF, `<robot>` URDF,
    /// anything else JSON.
    #[default]
    Detect,
    /// gymfleet's assembly JSON.
    Json,
    /// ROS's URDF (not converted yet: the server refuses it).
    Urdf,
    /// MuJoCo's XML.
    Mjcf,
}

impl From<DocumentFormat> for pb::DocumentFormat {
    fn from(f: DocumentFormat) -> Self {
        match f {
            DocumentFormat::Detect => pb::DocumentFormat::Unspecified,
            DocumentFormat::Json => pb::DocumentFormat::Json,
            DocumentFormat::Urdf => pb::DocumentFormat::Urdf,
            DocumentFormat::Mjcf => pb::DocumentFormat::Mjcf,
        }
    }
}

/// A description converted by the server.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvertedDocument {
    /// The assembly JSON the server builds envs from.
    pub document_json: String,
    /// What the conversion ignored (no effect on the dynamics), one line each.
    pub warnings: Vec<String>,
    /// The description's format, as detected.
    pub format: DocumentFormat,
}

/// A model of a server's library ([`Client::list_models`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelInfo {
    /// The name to give [`crate::EnvOptions::from_model`].
    pub name: String,
    /// Its file's format.
    pub format: DocumentFormat,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Values per action.
    pub action_dim: usize,
}

fn format_of(raw: i32) -> DocumentFormat {
    match pb::DocumentFormat::try_from(raw) {
        Ok(pb::DocumentFormat::Mjcf) => DocumentFormat::Mjcf,
        Ok(pb::DocumentFormat::Urdf) => DocumentFormat::Urdf,
        Ok(pb::DocumentFormat::Json) => DocumentFormat::Json,
        _ => DocumentFormat::Detect,
    }
}

impl Client {
    /// The server's model library (`--models DIR`), by name; empty without one.
    pub async fn list_models(&self) -> Result<Vec<ModelInfo>> {
        let reply = self
            .rpc()
            .list_models(pb::ListModelsRequest {})
            .await?
            .into_inner();
        Ok(reply
            .models
            .into_iter()
            .map(|m| ModelInfo {
                name: m.name,
                format: format_of(m.format),
                dofs: m.dofs as usize,
                action_dim: m.action_dim as usize,
            })
            .collect())
    }

    /// The assembly JSON the server builds from `document` (MJCF, or JSON checked and
    /// returned as is), with the conversion's warnings: see and edit what will be built.
    pub async fn convert_document(
        &self,
        document: impl Into<String>,
        format: DocumentFormat,
    ) -> Result<ConvertedDocument> {
        self.convert_document_with_assets(document, format, Vec::new())
            .await
    }

    /// [`Client::convert_document`] for a description that references mesh files, given
    /// as one zip, tar or tar.gz archive (see [`EnvOptions::assets`](crate::EnvOptions::assets)):
    /// the meshes are read into the returned document.
    pub async fn convert_document_with_assets(
        &self,
        document: impl Into<String>,
        format: DocumentFormat,
        assets: impl Into<Vec<u8>>,
    ) -> Result<ConvertedDocument> {
        self.convert_document_in(document, format, assets, "").await
    }

    /// [`Client::convert_document_with_assets`] for a document at `document_path` in its
    /// assets (see [`crate::EnvOptions::document_path`]).
    pub async fn convert_document_in(
        &self,
        document: impl Into<String>,
        format: DocumentFormat,
        assets: impl Into<Vec<u8>>,
        document_path: &str,
    ) -> Result<ConvertedDocument> {
        let request = pb::ConvertDocumentRequest {
            document_json: document.into(),
            format: pb::DocumentFormat::from(format) as i32,
            assets: assets.into(),
            document_path: document_path.to_string(),
        };
        self.check_request_size(&request, request.document_json.len(), request.assets.len())?;
        let reply = self.rpc().convert_document(request).await?.into_inner();
        Ok(ConvertedDocument {
            document_json: reply.document_json,
            warnings: reply.warnings,
            format: format_of(reply.format),
        })
    }
}
