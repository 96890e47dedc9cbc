
ƒ{
  "parts": [
    {
      "name": "Frame",
      "primitive": {
        "type": "cube",
        "size": {
          "x": 150,
          "y": 20,
          "z": 8
        }
      }
    },
    {
      "name": "Crank",
      "primitive": {
        "type": "cube",
        "size": {
          "x": 40.0,
          "y": 6.0,
          "z": 6.0
        }
      }
    },
    {
      "name": "Coupler",
      "primitive": {
        "type": "cube",
        "size": {
          "x": 120.0,
          "y": 6.0,
          "z": 6.0
        }
      }
    },
    {
      "name": "Rocker",
      "primitive": {
        "type": "cube",
        "size": {
          "x": 100.0,
          "y": 6.0,
          "z": 6.0
        }
      }
    }
  ],
  "assembly": {
    "instances": [
      {
        "part": "Frame",
        "name": "frame",
        "position": {
          "x": -20,
          "y": -10,
          "z": -40
        },
        "collision": {
          "group": 0,
          "mask": 0
        }
      },
      {
        "part": "Crank",
        "name": "crank",
        "position": {
          "x": 2.5981,
          "y": -3.0,
          "z": -1.5
        },
        "rotation": {
          "x": 0,
          "y": -60.0,
          "z": 0
        },
        "collision": {
          "group": 0,
          "mask": 0
        }
      },
      {
        "part": "Coupler",
        "name": "coupler",
        "position": {
          "x": 21.6187,
          "y": -3.0,
          "z": 32.1152
        },
        "rotation": {
          "x": 0,
          "y": -32.6544,
          "z": 0
        },
        "collision": {
          "group": 0,
          "mask": 0
        }
      },
      {
        "part": "Rocker",
        "name": "rocker",
        "position": {
          "x": 112.9817,
          "y": -3.0,
          "z": -0.331
        },
        "rotation": {
          "x": 0,
          "y": -83.6658,
          "z": 0
        },
        "collision": {
          "group": 0,
          "mask": 0
        }
      }
    ],
    "joints": [
      {
        "name": "crank",
        "type": "revolute",
        "parent": "frame",
        "child": "crank",
        "anchor": {
          "x": 0,
          "y": 0,
          "z": 0
        },
        "axis": {
          "x": 0,
          "y": -1,
          "z": 0
        },
        "max_effort": 2.0
      },
      {
        "name": "elbow",
        "type": "revolute",
        "parent": "crank",
        "child": "coupler",
        "anchor": {
          "x": 20.0,
          "y": 0,
          "z": 34.641
        },
        "axis": {
          "x": 0,
          "y": -1,
          "z": 0
        },
        "actuated": false
      },
      {
        "name": "rocker",
        "type": "revolute",
        "parent": "frame",
        "child": "rocker",
        "anchor": {
          "x": 110.0,
          "y": 0,
          "z": 0
        },
        "axis": {
          "x": 0,
          "y": -1,
          "z": 0
        },
        "actuated": false
      },
      {
        "name": "pin",
        "type": "revolute",
        "parent": "coupler",
        "child": "rocker",
        "anchor": {
          "x": 121.0328,
          "y": 0,
          "z": 99.3895
        },
        "axis": {
          "x": 0,
          "y": -1,
          "z": 0
        },
        "actuated": false
      }
    ]
  }
}
(