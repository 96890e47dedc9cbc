
Ð.{
"parts": [
{ "name": "Base", "primitive": { "type": "cube", "size": { "x": 20, "y": 20, "z": 5 } }, "material": "aluminium" },
{ "name": "Link", "primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 20 } }, "material": "aluminium" }
],
"materials": {
"aluminium": { "density": 2700, "friction": 0.5, "restitution": 0.0 }
},
"assembly": {
"instances": [
{ "part": "Base", "name": "base" },
{ "part": "Link", "name": "link1", "position": { "x": 8, "y": 8, "z": 5 } },
{ "part": "Link", "name": "link2", "position": { "x": 8, "y": 8, "z": 25 } },
{ "part": "Link", "name": "link3", "position": { "x": 8, "y": 8, "z": 45 } },
{ "part": "Link", "name": "link4", "position": { "x": 8, "y": 8, "z": 65 } },
{ "part": "Link", "name": "link5", "position": { "x": 8, "y": 8, "z": 85 } },
{ "part": "Link", "name": "link6", "position": { "x": 8, "y": 8, "z": 105 } },
{ "part": "Link", "name": "link7", "position": { "x": 8, "y": 8, "z": 125 } },
{ "part": "Link", "name": "link8", "position": { "x": 8, "y": 8, "z": 145 } },
{ "part": "Link", "name": "link9", "position": { "x": 8, "y": 8, "z": 165 } },
{ "part": "Link", "name": "link10", "position": { "x": 8, "y": 8, "z": 185 } },
{ "part": "Link", "name": "link11", "position": { "x": 8, "y": 8, "z": 205 } },
{ "part": "Link", "name": "link12", "position": { "x": 8, "y": 8, "z": 225 } },
{ "part": "Link", "name": "link13", "position": { "x": 8, "y": 8, "z": 245 } },
{ "part": "Link", "name": "link14", "position": { "x": 8, "y": 8, "z": 265 } },
{ "part": "Link", "name": "link15", "position": { "x": 8, "y": 8, "z": 285 } },
{ "part": "Link", "name": "link16", "position": { "x": 8, "y": 8, "z": 305 } },
{ "part": "Link", "name": "link17", "position": { "x": 8, "y": 8, "z": 325 } },
{ "part": "Link", "name": "link18", "position": { "x": 8, "y": 8, "z": 345 } },
{ "part": "Link", "name": "link19", "position": { "x": 8, "y": 8, "z": 365 } },
{ "part": "Link", "name": "link20", "position": { "x": 8, "y": 8, "z": 385 } }
],
"joints": [
{ "type": "revolute", "name": "j1", "parent": "base", "child": "link1", "anchor": { "x": 10, "y": 10, "z": 5 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j2", "parent": "link1", "child": "link2", "anchor": { "x": 10, "y": 10, "z": 25 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j3", "parent": "link2", "child": "link3", "anchor": { "x": 10, "y": 10, "z": 45 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j4", "parent": "link3", "child": "link4", "anchor": { "x": 10, "y": 10, "z": 65 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j5", "parent": "link4", "child": "link5", "anchor": { "x": 10, "y": 10, "z": 85 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j6", "parent": "link5", "child": "link6", "anchor": { "x": 10, "y": 10, "z": 105 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j7", "parent": "link6", "child": "link7", "anchor": { "x": 10, "y": 10, "z": 125 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j8", "parent": "link7", "child": "link8", "anchor": { "x": 10, "y": 10, "z": 145 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j9", "parent": "link8", "child": "link9", "anchor": { "x": 10, "y": 10, "z": 165 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j10", "parent": "link9", "child": "link10", "anchor": { "x": 10, "y": 10, "z": 185 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j11", "parent": "link10", "child": "link11", "anchor": { "x": 10, "y": 10, "z": 205 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j12", "parent": "link11", "child": "link12", "anchor": { "x": 10, "y": 10, "z": 225 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j13", "parent": "link12", "child": "link13", "anchor": { "x": 10, "y": 10, "z": 245 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j14", "parent": "link13", "child": "link14", "anchor": { "x": 10, "y": 10, "z": 265 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j15", "parent": "link14", "child": "link15", "anchor": { "x": 10, "y": 10, "z": 285 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j16", "parent": "link15", "child": "link16", "anchor": { "x": 10, "y": 10, "z": 305 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j17", "parent": "link16", "child": "link17", "anchor": { "x": 10, "y": 10, "z": 325 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j18", "parent": "link17", "child": "link18", "anchor": { "x": 10, "y": 10, "z": 345 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j19", "parent": "link18", "child": "link19", "anchor": { "x": 10, "y": 10, "z": 365 }, "axis": { "x": 0, "y": 1, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 },
{ "type": "revolute", "name": "j20", "parent": "link19", "child": "link20", "anchor": { "x": 10, "y": 10, "z": 385 }, "axis": { "x": 1, "y": 0, "z": 0 }, "min": -150, "max": 150, "damping": 0.0001 }
]
}
}
(