// The "New" menu: a small, valid, commented document of each kind to start from.

export const templates = {
  tga: `// A new timed game: a lamp that follows a button (after Peter 2005, figure 7.4).
// Components under "plant", forbidden combinations under "assertions", the production plan
// under "plans"; ?requests are the controller's, !reactions the plant's.
plant {
  automaton lamp {
    nodes off, on;
    off -> on ?turn_on;
    on -> off ?turn_off;
  }
  automaton button {
    clocks c;
    nodes released, pressing {c in [0,1)}, pressed, releasing {c in [0,1)};
    released -> pressing !press reset{c};
    pressing -> pressed !press_settled {c in (0,1)};
    pressed -> releasing !release reset{c};
    releasing -> released !release_settled {c in (0,1)};
  }
}

assertions {
  never lamp.off and button.pressed;
  never lamp.on and button.released;
}

plans {
  plan {
    waitfor press;
    waitfor release;
  }
}
`,
  sct: `// A new supervisory-control project: a tank that must not overflow.
// Events with their kind, plant models with their alphabet, specifications with prohibitions.
event openInlet : controllable { detect rising "Q_Inlet"; reset on denial "Q_Inlet"; }
event closeInlet : controllable { detect falling "Q_Inlet"; }
event levelAlarm : uncontrollable { detect rising "I_LevelHigh"; }
event overflow : uncontrollable;

plant Inlet {
  alphabet openInlet, closeInlet, levelAlarm, overflow;
  state A initial { openInlet -> B; closeInlet -> A; }
  state B { openInlet -> B; closeInlet -> A; levelAlarm -> C; }
  state C { openInlet -> C; closeInlet -> A; overflow -> C; }
}

spec NoOverflow {
  state S { forbid overflow; }
}
`,
  ltl: `// A new LTL specification in G4LTL's lines: inputs, outputs, then one formula per line;
// ASSUME marks an assumption about the environment.
INPUT req
OUTPUT grant
ALWAYS (req -> NEXT grant)
ALWAYS (!req -> NEXT !grant)
`,
  tlsf: `// A new LTL specification in SYNTCOMP's TLSF.
INFO {
  TITLE:       "Echo"
  DESCRIPTION: "The output follows the input one step later"
  SEMANTICS:   Mealy
  TARGET:      Mealy
}
MAIN {
  INPUTS { r; }
  OUTPUTS { g; }
  GUARANTEES {
    G (r <-> X g);
  }
}
`,
};
