//! Stage 3, scene: `ir::SceneDesc` + assets (via the `Loader`) → render-ready `Scene`
//! (world geometry and BVH, textures, light sampling tables, camera), only what the scene uses.
