
Þ{
"parts": [
{ "name": "Base", "primitive": { "type": "cylinder", "radius": 15, "height": 5 } },
{ "name": "Upper Arm", "primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 30 } } },
{ "name": "Forearm", "primitive": { "type": "cube", "size": { "x": 3, "y": 3, "z": 25 } } }
],
"assembly": {
"instances": [
{ "part": "Base", "name": "base" },
{ "part": "Upper Arm", "name": "upper", "position": { "x": -2, "y": -2, "z": 5 } },
{ "part": "Forearm", "name": "forearm", "position": { "x": -1.5, "y": -1.5, "z": 35 } }
],
"joints": [
{
"type": "revolute",
"parent": "base",
"child": "upper",
"anchor": { "x": 0, "y": 0, "z": 5 },
"axis": { "x": 0, "y": 1, "z": 0 },
"min": -90,
"max": 90
},
{
"type": "revolute",
"parent": "upper",
"child": "forearm",
"anchor": { "x": 0, "y": 0, "z": 35 },
"axis": { "x": 0, "y": 1, "z": 0 },
"min": -120,
"max": 0
}
]
}
}
(