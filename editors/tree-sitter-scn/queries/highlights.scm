;; Highlights for scnc scene files (.scn), with the standard capture names of Neovim and Zed
;; (for Helix, see editors/README.md). The patterns do not overlap (each node gets one capture
;; whatever the editor's precedence rule), and every word list is checked against the
;; compiler's tables by tests/editors_drift.rs: keep one list per predicate.

(line_comment) @comment
(block_comment) @comment

(string) @string
(escape_sequence) @string.escape
(number) @number
((unit) @keyword.unit
  (#any-of? @keyword.unit
    "deg" "rad"))
((unit) @error
  (#not-any-of? @error "deg" "rad"))
(hex_color) @constant
(array) @number

[
    "scnc" "include" "let" "camera" "material" "texture"
    "mesh" "light" "object" "group" "render" "transform"
] @keyword

"=" @operator
(binary_expression operator: _ @operator)
(negation "-" @operator)
["{" "}" "(" ")"] @punctuation.bracket
"," @punctuation.delimiter

; Declared names and references.
(let name: (identifier) @constant)
(camera name: (identifier) @type)
(declaration name: (identifier) @type)
(group name: (identifier) @type)
(object mesh: (identifier) @variable)

; The kind after `=`: `phong`, `sphere`, `image("wood.png")`, ...
(declaration kind: (identifier) @type.builtin)
((call function: (identifier) @type.builtin)
  (#any-of? @type.builtin
    "area" "box" "checker" "constant" "environment" "icosphere" "image" "inline" "obj"
    "phong" "point" "quad" "sphere"))

; Built-in functions (the colour constructors among them).
((call function: (identifier) @function.builtin)
  (#any-of? @function.builtin
    "rgb" "linear" "srgb" "sin" "cos" "tan" "sqrt" "abs"
    "min" "max" "pow" "radians" "degrees" "normalize" "length" "dot"
    "cross"))
((call function: (identifier) @function)
  (#not-any-of? @function
    "area" "box" "checker" "constant" "environment" "icosphere" "image" "inline" "obj"
    "phong" "point" "quad" "sphere" "rgb" "linear" "srgb" "sin"
    "cos" "tan" "sqrt" "abs" "min" "max" "pow" "radians"
    "degrees" "normalize" "length" "dot" "cross"))

; Block items: property keys, the bare words some keys take, booleans, references.
((block (identifier) @property)
  (#any-of? @property
    "ambient" "camera" "color" "diffuse" "encoding" "even" "exposure" "eye"
    "filter" "fov" "image" "indices" "intensity" "light_samples" "look_at" "max_samples" "noise" "quality" "max_samples" "noise" "quality" "material"
    "matrix" "mesh" "mtl" "normal_green" "normal_map" "normal_strength" "normals" "odd" "output"
    "position" "positions" "quad" "radiance" "radius" "resolution" "rotate" "samples"
    "scale" "seed" "segments" "shininess" "size" "specular" "subdivisions" "target" "tonemap"
    "translate" "two_sided" "up" "uvs" "visible" "wrap"))
((block (identifier) @constant.builtin)
  (#any-of? @constant.builtin
    "anisotropic" "bilinear" "clamp" "data" "directx" "filmic" "grid" "mirror" "nearest"
    "opengl" "reinhard" "draft" "preview" "final" "draft" "preview" "final" "repeat" "rgss" "srgb" "trilinear"))
((identifier) @boolean
  (#any-of? @boolean "true" "false"))
((block (identifier) @variable)
  (#not-any-of? @variable
    "ambient" "camera" "color" "diffuse" "encoding" "even" "exposure" "eye"
    "filter" "fov" "image" "indices" "intensity" "light_samples" "look_at" "max_samples" "noise" "quality" "max_samples" "noise" "quality" "material"
    "matrix" "mesh" "mtl" "normal_green" "normal_map" "normal_strength" "normals" "odd" "output"
    "position" "positions" "quad" "radiance" "radius" "resolution" "rotate" "samples"
    "scale" "seed" "segments" "shininess" "size" "specular" "subdivisions" "target" "tonemap"
    "translate" "two_sided" "up" "uvs" "visible" "wrap" "anisotropic" "bilinear" "clamp"
    "data" "directx" "filmic" "grid" "mirror" "nearest" "opengl" "reinhard" "draft" "preview" "final" "draft" "preview" "final"
    "repeat" "rgss" "srgb" "trilinear" "true" "false"))
((binary_expression (identifier) @variable)
  (#not-any-of? @variable "true" "false"))
((negation (identifier) @variable)
  (#not-any-of? @variable "true" "false"))
((parenthesized (identifier) @variable)
  (#not-any-of? @variable "true" "false"))
((arguments (identifier) @variable)
  (#not-any-of? @variable "true" "false"))
((let value: (identifier) @variable)
  (#not-any-of? @variable "true" "false"))
