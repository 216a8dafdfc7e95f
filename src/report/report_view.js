/*
 * report_view.js: the HTML report's 3D view (report_html.c) in WebGL through three.js
 * (embedded in the page before this script): the restored part (grey), the patches
 * (orange, drawn in front of the part's coincident faces) and, when the page has it,
 * the scan (blue), each a mesh of its own shown or hidden by its checkbox. The camera
 * opens on the damage: aimed at the centroid of the largest section's patch, from
 * outside the part along the line from the part's centre through the patch, the part's
 * axis (the aligned frame's z) up. Drag rotates about the aimed point, shift-drag or
 * right-drag pans, the wheel zooms; frames are drawn on demand only. Without WebGL the
 * canvas gives way to a note. Sets body's data-view ("webgl", "fallback", "none"),
 * data-gl (the renderer) and data-redraw-ms (the last frame's time). Plain ES5.
 * The second function draws the inspection's scan after repair (data.inspection) on
 * its own canvas, each vertex coloured by its signed deviation through the page's
 * colour stops (the legend's), seen from outside the part on the side where the
 * deviations beyond the tolerance lie (their centroid), the axis up; drag
 * rotates, the wheel zooms. Sets body's data-inspect-view ("webgl", "fallback", "none").
 * Compiled into the binary by the Makefile (report_assets.h), this opening comment left
 * out, every line as it is.
 */
(function(){'use strict';
var data=JSON.parse(document.getElementById('report-data').textContent);
var cv=document.getElementById('view'),body=document.body;
function b64(s){var t=atob(s),u=new Uint8Array(t.length);for(var i=0;i<t.length;i++)u[i]=t.charCodeAt(i);return u.buffer;}
function arrays(m){return {v:new Float32Array(b64(m.v),0,3*m.nv),t:new Uint32Array(b64(m.t),0,3*m.nt)};}
var parts=[];
if(data.restored)parts.push({m:arrays(data.restored),col:0xa8b0bc,box:'show-part',front:false});
data.patches.forEach(function(p){parts.push({m:arrays(p.mesh),col:0xe8601c,box:'show-patches',front:true,vol:p.volume_mm3});});
if(data.scan)parts.push({m:arrays(data.scan),col:0x3d7fd9,box:'show-scan',front:false});
function fallback(why){if(cv)cv.hidden=true;var f=document.getElementById('view-fallback');if(f&&why==='fallback')f.hidden=false;body.setAttribute('data-view',why);}
if(!cv||!parts.length){fallback('none');return;}
var probe=document.createElement('canvas'),pg=window.WebGLRenderingContext&&(probe.getContext('webgl')||probe.getContext('experimental-webgl'));
if(!window.THREE||!pg){fallback('fallback');return;}
/* a software renderer (SwiftShader, llvmpipe) pays for antialiasing on the CPU: it
 * costs such a frame about twice its time, so it is left off there */
var dri=pg.getExtension('WEBGL_debug_renderer_info'),gpu=dri?String(pg.getParameter(dri.UNMASKED_RENDERER_WEBGL)):'';
var soft=/swiftshader|llvmpipe|softpipe|software/i.test(gpu),T=window.THREE,renderer;
try{renderer=new T.WebGLRenderer({canvas:cv,antialias:!soft,preserveDrawingBuffer:true});}catch(e){fallback('fallback');return;}
body.setAttribute('data-gl',(soft?'software ':'')+gpu);
renderer.setClearColor(0xffffff,1);
var scene=new T.Scene(),lo=new T.Vector3(Infinity,Infinity,Infinity),hi=new T.Vector3(-Infinity,-Infinity,-Infinity);
parts.forEach(function(e){var g=new T.BufferGeometry();g.setAttribute('position',new T.BufferAttribute(e.m.v,3));g.setIndex(new T.BufferAttribute(e.m.t,1));
 var mat=new T.MeshPhongMaterial({color:e.col,flatShading:true,side:T.DoubleSide,shininess:12,polygonOffset:e.front,polygonOffsetFactor:e.front?-2:0,polygonOffsetUnits:e.front?-4:0});
 e.mesh=new T.Mesh(g,mat);scene.add(e.mesh);g.computeBoundingBox();
 if(e.box!=='show-scan'||parts.length===1){lo.min(g.boundingBox.min);hi.max(g.boundingBox.max);}
 var c=document.getElementById(e.box);if(c){e.mesh.visible=c.checked;c.addEventListener('change',function(){e.mesh.visible=c.checked;later();});}});
var ctr=lo.clone().add(hi).multiplyScalar(0.5),rad=Math.max(1e-6,hi.clone().sub(lo).length()/2);
var camera=new T.PerspectiveCamera(35,cv.width/cv.height,rad/100,rad*100);
scene.add(camera);var sun=new T.DirectionalLight(0xffffff,0.75);sun.position.set(0.3,0.6,1);camera.add(sun);
scene.add(new T.AmbientLight(0xffffff,0.45));
/* the aim: the largest patch's centroid, seen from outside along centre -> patch */
var aim={target:ctr.clone(),dir:new T.Vector3(1,-1,0.6).normalize(),h:rad};
var up=new T.Vector3(0,0,1);
if(data.alignment){var A=data.alignment;up.set(A[8],A[9],A[10]);if(!(up.length()>0))up.set(0,0,1);up.normalize();}
var big=null;parts.forEach(function(e){if(e.front&&(!big||e.vol>big.vol))big=e;});
if(big){var v=big.m.v,n=v.length/3,c=new T.Vector3(),pl=new T.Vector3(Infinity,Infinity,Infinity),ph=new T.Vector3(-Infinity,-Infinity,-Infinity),q=new T.Vector3();
 for(var i=0;i<n;i++){q.set(v[3*i],v[3*i+1],v[3*i+2]);c.add(q);pl.min(q);ph.max(q);}
 c.multiplyScalar(1/Math.max(1,n));var d=c.clone().sub(ctr);
 aim.target=c;aim.h=Math.max(0.55*rad,1.6*ph.clone().sub(pl).length());
 if(d.length()>1e-3*rad)aim.dir=d.normalize();
 /* a little from above along the axis, so the loss shows its depth */
 if(Math.abs(aim.dir.dot(up))<0.8)aim.dir.addScaledVector(up,0.35).normalize();}
if(Math.abs(aim.dir.dot(up))>0.97)up=Math.abs(aim.dir.z)<0.9?new T.Vector3(0,0,1):new T.Vector3(1,0,0);
camera.up.copy(up);
function home(){var dist=Math.max(aim.h/Math.tan(17.5*Math.PI/180),aim.target.distanceTo(ctr)+1.2*rad);
 camera.position.copy(aim.target).addScaledVector(aim.dir,dist);camera.up.copy(up);target.copy(aim.target);camera.lookAt(target);}
var target=new T.Vector3(),pending=false;
function draw(){pending=false;var t0=performance.now();renderer.render(scene,camera);
 var gl=renderer.getContext();if(gl&&gl.finish)gl.finish();body.setAttribute('data-redraw-ms',(performance.now()-t0).toFixed(1));}
function later(){if(!pending){pending=true;window.requestAnimationFrame(draw);}}
home();
/* orbit, pan, zoom about the target */
var drag=null;
cv.addEventListener('contextmenu',function(ev){ev.preventDefault();});
cv.addEventListener('pointerdown',function(ev){drag={x:ev.clientX,y:ev.clientY,pan:ev.shiftKey||ev.button===2};cv.setPointerCapture(ev.pointerId);});
cv.addEventListener('pointerup',function(){drag=null;});
cv.addEventListener('pointermove',function(ev){if(!drag)return;var dx=ev.clientX-drag.x,dy=ev.clientY-drag.y;drag.x=ev.clientX;drag.y=ev.clientY;
 var off=camera.position.clone().sub(target),right=new T.Vector3().crossVectors(off,camera.up).normalize();
 if(drag.pan){var s=off.length()*0.0015,u=new T.Vector3().crossVectors(right,off).normalize();
  var m=right.multiplyScalar(dx*s).add(u.multiplyScalar(-dy*s));target.add(m);camera.position.add(m);}
 else{off.applyQuaternion(new T.Quaternion().setFromAxisAngle(camera.up,-dx*0.01));
  var r2=new T.Vector3().crossVectors(off,camera.up).normalize(),o2=off.clone().applyQuaternion(new T.Quaternion().setFromAxisAngle(r2,-dy*0.01));
  if(Math.abs(o2.clone().normalize().dot(camera.up))<0.995)off=o2;camera.position.copy(target).add(off);}
 camera.lookAt(target);later();});
cv.addEventListener('wheel',function(ev){ev.preventDefault();var off=camera.position.clone().sub(target).multiplyScalar(ev.deltaY<0?1/1.1:1.1);camera.position.copy(target).add(off);later();},{passive:false});
var rs=document.getElementById('reset-view');if(rs)rs.addEventListener('click',function(){home();later();});
draw();body.setAttribute('data-view','webgl');
})();
(function(){'use strict';
var data=JSON.parse(document.getElementById('report-data').textContent),ins=data.inspection;
var cv=document.getElementById('inspect-view'),body=document.body;
if(!ins||!ins.scan||!cv){body.setAttribute('data-inspect-view','none');return;}
var T=window.THREE,renderer;
function b64(s){var t=atob(s),u=new Uint8Array(t.length);for(var i=0;i<t.length;i++)u[i]=t.charCodeAt(i);return u.buffer;}
try{if(!T||!window.WebGLRenderingContext)throw 0;renderer=new T.WebGLRenderer({canvas:cv,antialias:false,preserveDrawingBuffer:true});}
catch(e){cv.hidden=true;body.setAttribute('data-inspect-view','fallback');return;}
renderer.setClearColor(0xffffff,1);
var m=ins.scan,v=new Float32Array(b64(m.v),0,3*m.nv),t=new Uint32Array(b64(m.t),0,3*m.nt),dev=new Float32Array(b64(ins.deviation),0,m.nv);
var st=ins.stops.map(function(s){return {at:s[0],c:new T.Color(s[1])};}),col=new Float32Array(3*m.nv);
/* the colour of d: linear between the stops around it, the end colours beyond them */
function colour(d){if(!(d>st[0].at))return st[0].c;var n=st.length;if(d>=st[n-1].at)return st[n-1].c;
 for(var i=0;i+1<n;i++)if(d<=st[i+1].at&&st[i+1].at>st[i].at){var f=(d-st[i].at)/(st[i+1].at-st[i].at);return st[i].c.clone().lerp(st[i+1].c,Math.max(0,Math.min(1,f)));}
 return st[n-1].c;}
for(var i=0;i<m.nv;i++){var c=colour(dev[i]);col[3*i]=c.r;col[3*i+1]=c.g;col[3*i+2]=c.b;}
var g=new T.BufferGeometry();g.setAttribute('position',new T.BufferAttribute(v,3));g.setAttribute('color',new T.BufferAttribute(col,3));g.setIndex(new T.BufferAttribute(t,1));
var mat=new T.MeshPhongMaterial({vertexColors:T.VertexColors!==undefined?T.VertexColors:true,flatShading:true,side:T.DoubleSide,shininess:8});
var scene=new T.Scene();scene.add(new T.Mesh(g,mat));g.computeBoundingBox();
var ctr=g.boundingBox.min.clone().add(g.boundingBox.max).multiplyScalar(0.5),rad=Math.max(1e-6,g.boundingBox.max.clone().sub(g.boundingBox.min).length()/2);
var camera=new T.PerspectiveCamera(35,cv.width/cv.height,rad/100,rad*100);scene.add(camera);
var sun=new T.DirectionalLight(0xffffff,0.7);sun.position.set(0.3,0.6,1);camera.add(sun);scene.add(new T.AmbientLight(0xffffff,0.5));
var up=new T.Vector3(0,0,1);if(data.alignment){var A=data.alignment;up.set(A[8],A[9],A[10]);if(!(up.length()>0))up.set(0,0,1);up.normalize();}
/* seen from outside along centre -> the centroid of the vertices off the band, a little from above */
var dir=new T.Vector3(1,-1,0.6).normalize(),off=new T.Vector3(),no=0,tol=ins.tolerance_mm;
for(var i=0;i<m.nv;i++)if(Math.abs(dev[i])>tol){off.x+=v[3*i];off.y+=v[3*i+1];off.z+=v[3*i+2];no++;}
if(no){off.multiplyScalar(1/no).sub(ctr);if(off.length()>1e-3*rad){dir=off.normalize();if(Math.abs(dir.dot(up))<0.8)dir.addScaledVector(up,0.35).normalize();}}
if(Math.abs(dir.dot(up))>0.97)dir=Math.abs(up.z)<0.9?new T.Vector3(0,0,1):new T.Vector3(1,0,0);
camera.up.copy(up);camera.position.copy(ctr).addScaledVector(dir,rad/Math.tan(17.5*Math.PI/180)*1.05);camera.lookAt(ctr);
var pending=false;function draw(){pending=false;renderer.render(scene,camera);}
function later(){if(!pending){pending=true;window.requestAnimationFrame(draw);}}
var drag=null;
cv.addEventListener('pointerdown',function(ev){drag={x:ev.clientX,y:ev.clientY};cv.setPointerCapture(ev.pointerId);});
cv.addEventListener('pointerup',function(){drag=null;});
cv.addEventListener('pointermove',function(ev){if(!drag)return;var dx=ev.clientX-drag.x,dy=ev.clientY-drag.y;drag.x=ev.clientX;drag.y=ev.clientY;
 var off=camera.position.clone().sub(ctr);off.applyQuaternion(new T.Quaternion().setFromAxisAngle(camera.up,-dx*0.01));
 var r2=new T.Vector3().crossVectors(off,camera.up).normalize(),o2=off.clone().applyQuaternion(new T.Quaternion().setFromAxisAngle(r2,-dy*0.01));
 if(Math.abs(o2.clone().normalize().dot(camera.up))<0.995)off=o2;camera.position.copy(ctr).add(off);camera.lookAt(ctr);later();});
cv.addEventListener('wheel',function(ev){ev.preventDefault();var off=camera.position.clone().sub(ctr).multiplyScalar(ev.deltaY<0?1/1.1:1.1);camera.position.copy(ctr).add(off);later();},{passive:false});
draw();body.setAttribute('data-inspect-view','webgl');
})();
