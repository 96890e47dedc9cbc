
ê{
"parts": [
{ "name": "Base", "primitive": { "type": "cylinder", "radius": 40, "height": 20 }, "material": "steel" },
{ "name": "Turret", "primitive": { "type": "cylinder", "radius": 25, "height": 40 } },
{ "name": "Upper Arm", "primitive": { "type": "cube", "size": { "x": 20, "y": 20, "z": 160 } } },
{ "name": "Forearm", "primitive": { "type": "cube", "size": { "x": 16, "y": 16, "z": 140 } } },
{ "name": "Wrist Roll", "primitive": { "type": "cylinder", "radius": 10, "height": 30 } },
{ "name": "Wrist Pitch", "primitive": { "type": "cube", "size": { "x": 16, "y": 16, "z": 30 } } },
{ "name": "Tool", "primitive": { "type": "cylinder", "radius": 8, "height": 25 } }
],
"materials": {
"aluminium": { "density": 2700, "friction": 0.5, "restitution": 0.0 },
"steel": { "density": 7850, "friction": 0.6, "restitution": 0.0 }
},
"assembly": {
"instances": [
{ "part": "Base", "name": "base" },
{ "part": "Turret", "name": "turret", "position": { "x": 0, "y": 0, "z": 20 }, "material": "aluminium" },
{ "part": "Upper Arm", "name": "upper_arm", "position": { "x": -10, "y": -10, "z": 60 }, "material": "aluminium" },
{ "part": "Forearm", "name": "forearm", "position": { "x": -8, "y": -8, "z": 220 }, "material": "aluminium" },
{ "part": "Wrist Roll", "name": "wrist_roll", "position": { "x": 0, "y": 0, "z": 360 }, "material": "aluminium" },
{ "part": "Wrist Pitch", "name": "wrist_pitch", "position": { "x": -8, "y": -8, "z": 390 }, "material": "aluminium" },
{ "part": "Tool", "name": "tool", "position": { "x": 0, "y": 0, "z": 420 }, "material": "aluminium" }
],
"joints": [
{
"type": "revolute", "name": "base_yaw",
"parent": "base", "child": "turret",
"anchor": { "x": 0, "y": 0, "z": 20 }, "axis": { "x": 0, "y": 0, "z": 1 },
"min": -170, "max": 170, "damping": 0.002
},
{
"type": "revolute", "name": "shoulder_pitch",
"parent": "turret", "child": "upper_arm",
"anchor": { "x": 0, "y": 0, "z": 60 }, "axis": { "x": 0, "y": 1, "z": 0 },
"min": -100, "max": 100, "damping": 0.002
},
{
"type": "revolute", "name": "elbow_pitch",
"parent": "upper_arm", "child": "forearm",
"anchor": { "x": 0, "y": 0, "z": 220 }, "axis": { "x": 0, "y": 1, "z": 0 },
"min": -140, "max": 140, "damping": 0.002
},
{
"type": "revolute", "name": "wrist_roll",
"parent": "forearm", "child": "wrist_roll",
"anchor": { "x": 0, "y": 0, "z": 360 }, "axis": { "x": 0, "y": 0, "z": 1 },
"min": -180, "max": 180, "damping": 0.002
},
{
"type": "revolute", "name": "wrist_pitch",
"parent": "wrist_roll", "child": "wrist_pitch",
"anchor": { "x": 0, "y": 0, "z": 390 }, "axis": { "x": 0, "y": 1, "z": 0 },
"min": -110, "max": 110, "damping": 0.002
},
{
"type": "revolute", "name": "tool_roll",
"parent": "wrist_pitch", "child": "tool",
"anchor": { "x": 0, "y": 0, "z": 420 }, "axis": { "x": 0, "y": 0, "z": 1 },
"min": -180, "max": 180, "damping": 0.002
}
]
}
}
(