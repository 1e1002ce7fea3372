//! The table of every diagnostic code, by stage in pipeline order (see [`super::code`] for
//! what each entry defines). Adding a code: a line here and its `explain/STAGE/NAME.md`.

super::code::codes! {
    /// Reading the root scene file.
    io {
        IoRead = read: "the scene file cannot be read",
    }
    /// Decoding a scene file's bytes as text.
    source {
        SourceNotText = not_text: "a scene file is not UTF-8 text",
    }
    /// Stage 1, parsing.
    syntax {
        SyntaxEmpty = empty: "the scene file is empty",
        SyntaxMissingVersion = missing_version: "the file does not start with `scnc 1`",
        SyntaxUnsupportedVersion = unsupported_version: "the `scnc` header names a version this scnc does not read",
        SyntaxMisplacedVersion = misplaced_version: "a `scnc` header after the first statement",
        SyntaxUnknownKeyword = unknown_keyword: "a statement starts with a word that is not a statement keyword",
        SyntaxUnclosedDelimiter = unclosed_delimiter: "a `{`, `(` or `[` is never closed",
        SyntaxUnexpectedToken = unexpected_token: "the parser met something that cannot stand here",
        SyntaxTooDeep = too_deep: "brackets or blocks nested too deeply",
        SyntaxExpressionTooLarge = expression_too_large: "an expression with too many terms",
    }
    /// `include "file.scn"`.
    include {
        IncludeNotAString = not_a_string: "`include` is not followed by a file name string",
        IncludeNotFound = not_found: "an included file cannot be read",
        IncludeCycle = cycle: "a file includes itself, directly or through others",
        IncludeTooDeep = too_deep: "includes nested too deeply",
    }
    /// Stage 2, check: names.
    check {
        CheckDuplicateName = duplicate_name: "a name is declared twice",
        CheckReservedName = reserved_name: "a constant is named with a reserved word",
        CheckUnknownName = unknown_name: "a name in an expression is not declared",
        CheckUnknownMaterial = unknown_material: "no material has this name",
        CheckUnknownMesh = unknown_mesh: "no mesh has this name",
        CheckUnknownTexture = unknown_texture: "no texture has this name",
        CheckUnknownCamera = unknown_camera: "no camera has this name",
        CheckUnused = unused: "a declaration nothing uses",
        CheckNoCamera = no_camera: "the scene declares no camera",
        CheckDuplicateRender = duplicate_render: "more than one `render` block",
        CheckEmptyPath = empty_path: "an empty file name",
        CheckUnknownMaterialKind = unknown_material_kind: "the word after `material NAME =` is not a material kind",
        CheckUnknownTextureKind = unknown_texture_kind: "the word after `texture NAME =` is not a texture kind",
        CheckUnknownMeshKind = unknown_mesh_kind: "the word after `mesh NAME =` is not a mesh kind",
        CheckUnknownLightKind = unknown_light_kind: "the word after `light NAME =` is not a light kind",
        CheckUnknownKey = unknown_key: "a block has a key it does not take",
        CheckExpectedKey = expected_key: "a value stands where a block expects a key",
        CheckDuplicateKey = duplicate_key: "a key is given twice in one block",
        CheckMissingKey = missing_key: "a block lacks a key it needs",
        CheckConflictingKeys = conflicting_keys: "a block has two keys that exclude each other",
        CheckMisplacedBlock = misplaced_block: "a block is nested where it is not allowed",
        CheckWrongType = wrong_type: "a value of the wrong type",
        CheckWrongArity = wrong_arity: "the wrong number of values or arguments",
        CheckUnknownChoice = unknown_choice: "a key's word is not one of its choices",
        CheckExpectedName = expected_name: "a name was expected",
        CheckUnknownFunction = unknown_function: "a call to a function that does not exist",
        CheckUnknownUnit = unknown_unit: "a number has a unit suffix scnc does not know",
        CheckBadOperands = bad_operands: "an operator cannot combine these values",
        CheckUnexpectedArray = unexpected_array: "an array where a single value is expected",
        CheckBadVector = bad_vector: "a vector without 2 or 3 components",
        CheckBadArray = bad_array: "an array with a malformed element",
        CheckBadColor = bad_color: "a `#` colour that is not 3 or 6 hex digits",
        CheckNotFinite = not_finite: "an expression evaluates to infinity or NaN",
        CheckNotInteger = not_integer: "a fraction where a whole number is needed",
        CheckOutOfRange = out_of_range: "a number outside the range its key allows",
        CheckAngleWithoutUnit = angle_without_unit: "an angle written without `deg` or `rad`",
        CheckNegativeColor = negative_color: "a colour with a negative channel",
        CheckAlbedoOutOfRange = albedo_out_of_range: "a material reflects more light than it receives",
        CheckDarkLight = dark_light: "a light that emits nothing",
        CheckDegenerateQuad = degenerate_quad: "an area light's quad has no area",
        CheckDegenerateTransform = degenerate_transform: "a transform that flattens space or cannot be inverted",
        CheckZeroDirection = zero_direction: "a direction of zero length",
        CheckUpParallel = up_parallel: "a camera's `up` is parallel to its view direction",
        CheckIndexOutOfRange = index_out_of_range: "an inline mesh index past its positions",
        CheckLengthMismatch = length_mismatch: "an inline mesh's normals or uvs do not match its positions",
        CheckBadResolution = bad_resolution: "a resolution not written `WIDTH x HEIGHT`",
        CheckSamplesNotSquare = samples_not_square: "a sample count that is not a perfect square",
        CheckUnknownOutputFormat = unknown_output_format: "an output file whose extension names no image format",
        CheckSrgbNormalMap = srgb_normal_map: "a normal map decoded as an sRGB colour image",
    }
    /// Stage 3, scene build: files and geometry.
    build {
        BuildMissingFile = missing_file: "a file the scene names does not exist",
        BuildReadFailed = read_failed: "a file the scene names cannot be read",
        BuildIndexOutOfRange = index_out_of_range: "an OBJ face refers to a vertex that does not exist",
        BuildDegenerateMesh = degenerate_mesh: "every triangle of a mesh is degenerate",
        BuildDegenerateTriangles = degenerate_triangles: "some triangles of a mesh are degenerate and were dropped",
        BuildEmptyMesh = empty_mesh: "a mesh with no triangles",
        BuildSingularTransform = singular_transform: "an object's transform is singular or not finite",
        BuildUnsupported = unsupported: "a feature scnc does not support yet",
        BuildCorruptImage = corrupt_image: "an image file that cannot be decoded",
        BuildImageTooLarge = image_too_large: "an image larger than the size limit",
        BuildInvalidEnvironmentPixels = invalid_environment_pixels: "an environment map with negative, NaN or infinite pixels",
        BuildBlackEnvironment = black_environment: "an environment map that is black everywhere",
        BuildLightFacesAway = light_faces_away: "a one-sided area light faces away from all geometry",
        BuildNoUvs = no_uvs: "a textured material on a mesh without UV coordinates",
        BuildPrecisionLost = precision_lost: "an object f32 cannot place to a thousandth of its size",
        BuildNoCamera = no_camera: "the camera asked for does not exist",
    }
    /// Stage 3, OBJ and MTL files.
    obj {
        ObjTooLarge = too_large: "an OBJ file with more than 2³¹ vertices",
        ObjBadNumber = bad_number: "an OBJ or MTL number that cannot be read",
        ObjMissingNumber = missing_number: "an OBJ line with too few numbers",
        ObjShortFace = short_face: "an OBJ face with fewer than 3 corners",
        ObjBadIndex = bad_index: "an OBJ face index that is not a number",
        ObjIndexOutOfRange = index_out_of_range: "an OBJ face index past the vertices read so far",
        ObjUtf16 = utf16: "a UTF-16 OBJ file, transcoded",
        ObjNotUtf8 = not_utf8: "an OBJ or MTL file that is not UTF-8, read as Latin-1",
        ObjLinesSkipped = lines_skipped: "OBJ line and point elements, which are not surfaces",
        ObjPolygonFanned = polygon_fanned: "a large OBJ polygon triangulated as a fan",
        ObjPolygonRewound = polygon_rewound: "an OBJ face that goes round its corners more than once",
        ObjPolygonArea = polygon_area: "an OBJ face whose triangles do not cover its area exactly",
        ObjUnsupportedStatement = unsupported_statement: "OBJ statements scnc does not read",
        ObjMissingMtl = missing_mtl: "an OBJ's material library cannot be read",
        ObjUnknownMaterial = unknown_material: "an OBJ uses a material its libraries do not define",
        ObjMtlOutsideMaterial = mtl_outside_material: "an MTL statement before any `newmtl`",
        ObjBadMtlStatement = bad_mtl_statement: "an MTL statement that cannot be read",
        ObjUnsupportedMtl = unsupported_mtl: "MTL statements scnc does not render",
        ObjMissingTexture = missing_texture: "an MTL texture file cannot be read",
        ObjBadTexture = bad_texture: "an MTL texture that cannot be used",
        ObjTextureNotRendered = texture_not_rendered: "an MTL texture map scnc does not render",
        ObjUnknownOverride = unknown_override: "a material override names no material of the OBJ",
    }
    /// Stage 5, writing the image.
    write {
        WriteUnknownFormat = unknown_format: "an output path whose extension names no image format",
        WriteEncode = encode: "the image cannot be encoded in its format",
        WriteIo = io: "the image file cannot be written",
    }
    /// Command-line options.
    cli {
        CliUnknownCamera = unknown_camera: "`--camera` names no camera of the scene",
        CliTileNotExr = tile_not_exr: "`--tile K/N` with an output that is not an `.exr` file",
        CliTooManyTiles = too_many_tiles: "`--tile K/N` asks for more tiles than the image has rows",
        CliUnknownDefine = unknown_define: "`--define NAME=VALUE` names no `let` constant of the scene",
        CliDefineType = define_type: "`--define NAME=VALUE` gives a value of another type than the scene's",
        CliFramesWithoutPattern = frames_without_pattern: "`--frames` without `-o NAME_####.EXT` to number the files",
    }
    /// `scnc merge`: assembling the tiles of `scnc render --tile K/N`.
    merge {
        MergeUnreadable = unreadable: "a tile file cannot be read, or is truncated or corrupt",
        MergeNotATile = not_a_tile: "an OpenEXR file that is not a tile of `scnc render --tile`",
        MergeMismatch = mismatch: "tiles of different scenes or settings",
        MergeOverlap = overlap: "two tiles cover the same pixels",
        MergeMissing = missing: "the tiles do not cover the whole image",
    }
    /// `scnc inspect`.
    inspect {
        InspectReadFailed = read_failed: "the file to inspect cannot be read",
    }
}
