//! Frustum culling per patch (lead).
