
ç{
"parts": [
{
"name": "Base",
"primitive": { "type": "cube", "size": { "x": 20, "y": 20, "z": 5 } }
},
{
"name": "Arm",
"primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 40 } }
}
],
"assembly": {
"instances": [
{ "part": "Base", "name": "base" },
{ "part": "Arm", "name": "arm", "position": { "x": 8, "y": 8, "z": 5 } }
],
"joints": [
{
"type": "revolute",
"parent": "base",
"child": "arm",
"anchor": { "x": 10, "y": 10, "z": 5 },
"axis": { "x": 0, "y": 1, "z": 0 }
}
]
}
}
(