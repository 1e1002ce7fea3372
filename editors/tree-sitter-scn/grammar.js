/**
 * Tree-sitter grammar for scnc scene files (`.scn`), mirroring grammar/scene.pest (the one
 * grammar of the language; see grammar/README.md). Like the pest grammar it is structurally
 * permissive: a block is a flat list of terms and nested blocks; which words are property keys
 * is decided by the highlight queries from the compiler's word lists (checked by
 * tests/editors_drift.rs). Block comments nest, so they come from the external scanner
 * (src/scanner.c).
 */
module.exports = grammar({
  name: 'scn',

  extras: $ => [/[\s\uFEFF]/, $.line_comment, $.block_comment],
  externals: $ => [$.block_comment],
  word: $ => $.identifier,

  rules: {
    source_file: $ => repeat($._statement),

    _statement: $ => choice(
      $.version, $.include, $.let, $.camera, $.declaration, $.object, $.group, $.render,
    ),

    version: $ => seq('scnc', field('value', $._term)),
    include: $ => seq('include', field('path', $._term)),
    let: $ => seq('let', field('name', $.identifier), '=', field('value', $._expression)),
    camera: $ => seq('camera', field('name', $.identifier), field('body', $.block)),
    declaration: $ => seq(
      field('keyword', choice('material', 'texture', 'mesh', 'light')),
      field('name', $.identifier),
      '=',
      field('kind', choice($.call, $.identifier)),
      optional(field('body', $.block)),
    ),
    object: $ => seq('object', field('mesh', $.identifier), field('body', $.block)),
    group: $ => seq('group', field('name', $.identifier), field('body', $.block)),
    render: $ => seq('render', field('body', $.block)),

    block: $ => seq('{', repeat(choice($.transform, $.object, $.group, $._term)), '}'),
    transform: $ => seq('transform', field('body', $.block)),

    // `let` values, call arguments and parentheses hold arithmetic; a block value is one term.
    _expression: $ => choice($.binary_expression, $._term),
    binary_expression: $ => choice(
      prec.left(1, seq(field('left', $._expression), field('operator', choice('+', '-')), field('right', $._expression))),
      prec.left(2, seq(field('left', $._expression), field('operator', choice('*', '/')), field('right', $._expression))),
    ),
    _term: $ => choice($.negation, $._primary),
    negation: $ => prec(3, seq('-', $._term)),
    _primary: $ => choice($.call, $.identifier, $.number, $.parenthesized, $.hex_color, $.string, $.array),

    // The callee is written right before `(`: `rgb(1, 0, 0)`; `eye (0, 1, 2)` is a key and a vector.
    call: $ => seq(field('function', $.identifier), field('arguments', $.arguments)),
    arguments: $ => seq(token.immediate('('), optional(seq(commaSep1($._expression), optional(','))), ')'),
    // `(e)` groups; `(a, b)` and `(a, b, c)` are vectors.
    parenthesized: $ => seq('(', commaSep1($._expression), optional(','), ')'),

    number: $ => seq(
      /([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?/,
      optional(field('unit', $.unit)),
    ),
    unit: $ => token.immediate(/[A-Za-z_][A-Za-z0-9_]*/),
    hex_color: $ => /#[A-Za-z0-9]*/,
    string: $ => seq('"', repeat(choice($.string_content, $.escape_sequence)), token.immediate('"')),
    string_content: $ => token.immediate(prec(1, /[^"\\\n]+/)),
    escape_sequence: $ => token.immediate(/\\./),
    // One coarse token, as in the pest grammar: literal numbers only, no comments or `]` inside.
    array: $ => /\[[^\]]*\]/,

    identifier: $ => /[A-Za-z_][A-Za-z0-9_]*/,
    line_comment: $ => token(seq('//', /[^\n]*/)),
  },
});

function commaSep1(rule) {
  return seq(rule, repeat(seq(',', rule)));
}
